"""A challenge as storage keeps it (server/game/challenges.py tells its life)."""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict

from server.protocol.models import Challenge, ChallengeStatus, GameChoice, PlayerInfo


class ChallengeRecord(BaseModel):
    """A challenge as storage keeps it."""

    model_config = ConfigDict(frozen=True)

    id: str
    challenger: PlayerInfo
    challenged: PlayerInfo
    choice: GameChoice
    shot_clock: int = 0
    status: ChallengeStatus = ChallengeStatus.PENDING
    table: str | None = None
    created: float

    def wire(self) -> Challenge:
        return Challenge(**self.model_dump())
