"""The game service: the table actor and its typed commands (`actor`, `commands`), the table
record and its pure transitions (`tables`), the lobby and quick match, the shot clock, table
expiry, identities, ratings, the leaderboard, replays, the one seam to the rules
(`refereeing`) and the simulation worker processes (`workers`); `service` builds them once
per server process. It knows HTTP only through the handlers that call it (server/http)."""
