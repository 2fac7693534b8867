"""The game's wire protocol, shared by the server and every client: the request, answer and
channel message models (`models`), error codes (`errors`), every identifier, format, limit and
channel name (`ids`), the feed's relay constants (`feed`), the trajectories' wire form
(`trajectories`), and the browser's copy of the identifiers (`javascript`, which writes
web/src/net/protocol.js). It imports the rules' types it carries, never the game service."""
