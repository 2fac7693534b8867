"""What a subscriber of the game's channels reads on the relay's wire, beyond the messages
themselves (server/protocol/models.py): the WebSocket subprotocol, the gap notice's content
type and the close that means a channel was deleted. They are the relay's (server/relay), named
here so that clients depend on the protocol alone."""

from server.relay import CLOSE_GOING_AWAY, DELETED_REASON, GAP_TYPE, META_PROTOCOL

__all__ = ["CLOSE_GOING_AWAY", "DELETED_REASON", "GAP_TYPE", "META_PROTOCOL"]
