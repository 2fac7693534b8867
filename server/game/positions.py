"""Shared practice positions: a position checked and given its link, and a link read back.

A position link is the rules' compact form (`rules.compact.encode_position`), checked when it is
made and again when it is opened (a link may come from anyone): either way a position that
cannot start a rack, or a code that is no position link, is `bad_position` with the rules'
reason. Nothing is stored: the link carries the whole position.
"""

from __future__ import annotations

from server.game import refereeing
from server.game.tables import set_up
from server.protocol.errors import ErrorCode, ServiceError
from server.protocol.ids import practice_url
from server.protocol.models import PositionShare, SharedPosition, TableOptions


def _view(setup: refereeing.Setup) -> SharedPosition:
    assert setup.position is not None
    code = refereeing.share_code(setup)
    return SharedPosition(
        code=code,
        url=practice_url(setup.game, code),
        game=setup.game,
        size=setup.size,
        reds=setup.reds,
        position=setup.position,
    )


def share(request: PositionShare) -> SharedPosition:
    """The link of a player's position, once it is checked as a practice table checks one."""
    options = TableOptions(reds=request.reds, size=request.size)
    position = set_up(request.game, options, request.position)
    return _view(refereeing.rack_setup(request.game, options, 0, 0, position))


def open_link(code: str) -> SharedPosition:
    """What a shared position's code sets up, checked again."""
    try:
        return _view(refereeing.shared(code))
    except refereeing.RuleError as error:
        raise ServiceError(ErrorCode.BAD_POSITION, error.reason) from None
