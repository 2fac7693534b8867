"""Clients of the public API: the reconnecting API client (`api_client`) and `billiards play`
/ `watch` / `submit` (`play`). They depend on server/protocol alone, never on the server's
insides, so they are what any third-party client can be."""
