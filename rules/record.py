"""A game record that proves its game: setup, inputs, and what the inputs led to.

The engine is deterministic and the referees are pure, so setup and inputs determine every
state. A record also states what happened, so that a verifier can tell the game it replays from
the game the record claims: the engine version (always stored: another engine would replay
another game), after each input a 16-bit digest of the state it led to, and the final scores,
winner and a 64-bit digest of the whole game. `replay` recomputes all of them and refuses a
record whose replay differs anywhere, naming the first input where it does; an altered record
is refused whether or not its inputs are still legal.

The digests form a chain: each link hashes the previous link, the input and the state it led
to, so the final digest commits to every input and every state of the game (an input changed
without changing any state, such as the heading of a shot that pockets the cue ball and touches
nothing, is still caught), and each input's 16-bit digest is the start of its link. A state is
hashed with positions quantised to `POSITION_STEPS` (its other fields are integers and names),
as msgpack of its fields in their declared order; an input as msgpack of its JSON form.
"""

from __future__ import annotations

import hashlib
from typing import Annotated, Any

import msgpack
from pydantic import BaseModel, ConfigDict, Field, model_validator

import physics
from physics import ENGINE_VERSION
from rules.codes import Refusal, RuleError
from rules.game import Setup, Simulate, play, start
from rules.inputs import PlayerInput
from rules.spots import STANDARD_SIZE
from rules.state import Decision, State

#: More inputs than any real game needs: a record this long is refused, not replayed.
MAX_INPUTS = 5000
#: Positions are hashed in micrometres.
POSITION_STEPS = 1_000_000
#: Bytes of a chain link (the final digest) and of each input's digest.
LINK_BYTES, MARK_BYTES = 8, 2


def hashed_state(state: State) -> Any:
    """The state as plain data for hashing: positions quantised, balls sorted by name."""
    data = state.model_dump(mode="json")
    if state.size == STANDARD_SIZE:  # the standard table hashes as before sizes existed
        del data["size"]
    data["balls"] = [
        [b, round(x * POSITION_STEPS), round(y * POSITION_STEPS)]
        for b, (x, y) in sorted(state.balls.items())
    ]
    if state.retake is not None:
        data["retake"] = hashed_state(state.retake)
    return data


def link(previous: bytes, state: State, action: PlayerInput | None = None) -> bytes:
    """The next chain link: a hash of the previous link, the input and the state it led to
    (the first link, of the start, has no input)."""
    said = None if action is None else action.model_dump(mode="json")
    packed = msgpack.packb([said, hashed_state(state)])
    return hashlib.blake2b(previous + packed, digest_size=LINK_BYTES).digest()


def mark(chain: bytes) -> int:
    """An input's digest: the first MARK_BYTES of its link, as an integer."""
    return int.from_bytes(chain[:MARK_BYTES], "big")


Count = Annotated[int, Field(strict=True, ge=0)]
Hex = Annotated[str, Field(pattern=f"^[0-9a-f]{{{2 * LINK_BYTES}}}$")]


class Final(BaseModel):
    """The game as the record claims it ended: scores, winner (None: not over or no winner
    yet) and the last chain link (hex), which commits to every state."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    scores: tuple[Count, Count]
    winner: Annotated[int, Field(strict=True, ge=0, le=1)] | None = None
    digest: Hex


class GameRecord(BaseModel):
    """Engine version, rule set and rack (`setup`), every input in the order played with the
    digest of the state after it (`digests`, one per input), and the `final` result."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    engine: Annotated[str, Field(min_length=1, max_length=32)]
    setup: Setup
    inputs: Annotated[tuple[PlayerInput, ...], Field(max_length=MAX_INPUTS)] = ()
    digests: Annotated[
        tuple[Annotated[int, Field(strict=True, ge=0, lt=2 ** (8 * MARK_BYTES))], ...],
        Field(max_length=MAX_INPUTS),
    ] = ()
    final: Final

    @model_validator(mode="after")
    def _one_digest_per_input(self) -> GameRecord:
        if len(self.digests) != len(self.inputs):
            raise ValueError(f"{len(self.inputs)} inputs but {len(self.digests)} digests")
        return self

    @classmethod
    def begin(cls, setup: Setup, first: State | None = None) -> GameRecord:
        """The record of a game not yet played (`first`: its start, if already built)."""
        first = start(setup) if first is None else first
        chain = link(b"", first)
        return cls(
            engine=ENGINE_VERSION,
            setup=setup,
            final=Final(scores=first.scores, winner=first.winner, digest=chain.hex()),
        )

    def extend(self, action: PlayerInput, state: State) -> GameRecord:
        """This record with one more input, which led to `state`."""
        chain = link(bytes.fromhex(self.final.digest), state, action)
        return self.model_copy(
            update={
                "inputs": (*self.inputs, action),
                "digests": (*self.digests, mark(chain)),
                "final": Final(scores=state.scores, winner=state.winner, digest=chain.hex()),
            }
        )

    def to_json(self) -> str:
        """Compact JSON: fields at their defaults are left out (the engine is never defaulted)."""
        return self.model_dump_json(exclude_defaults=True)

    @classmethod
    def from_json(cls, text: str | bytes) -> GameRecord:
        return cls.model_validate_json(text)


class Step(BaseModel):
    """One input, the referee's decision if it was a shot, and the state it led to."""

    model_config = ConfigDict(frozen=True)

    action: PlayerInput
    decision: Decision | None
    state: State


class Replay(BaseModel):
    start: State
    steps: list[Step]

    @property
    def final(self) -> State:
        return self.steps[-1].state if self.steps else self.start


def _differs(n: int, what: str) -> RuleError:
    return RuleError(Refusal.REPLAY_DIFFERS, f"input #{n}: {what} differs from the record's")


def replay(
    record: GameRecord, simulate: Simulate = physics.simulate, until: int | None = None
) -> Replay:
    """Play the record's inputs from its rack and check every digest and the final result
    (`until`: play only the first `until` inputs, and check only their digests).

    Raises RuleError naming the first input (#1 is the first) that is illegal (its refusal's
    code) or whose replayed state differs from the record (REPLAY_DIFFERS), and refuses at
    once a record of another engine version (ENGINE_VERSION). An engine error names its input
    too (the engine's own exception type).
    """
    if record.engine != ENGINE_VERSION:
        raise RuleError(
            Refusal.ENGINE_VERSION,
            f"record played with engine {record.engine}, this is engine {ENGINE_VERSION}",
        )
    state = first = start(record.setup)
    chain = link(b"", first)
    steps = []
    for n, (action, digest) in enumerate(zip(record.inputs, record.digests, strict=True), 1):
        if until is not None and n > until:
            return Replay(start=first, steps=steps)
        try:
            outcome = play(state, action, simulate)
        except RuleError as exc:
            raise RuleError(exc.code, f"input #{n}: {exc.reason}") from None
        except (physics.SceneError, physics.SimulationError) as exc:
            raise type(exc)(f"input #{n}: {exc}") from exc
        state = outcome.state
        chain = link(chain, state, action)
        if mark(chain) != digest:
            raise _differs(n, "the input or the state it led to")
        steps.append(Step(action=action, decision=outcome.decision, state=state))
    last = len(record.inputs)
    claimed = record.final
    if (state.scores, state.winner) != (claimed.scores, claimed.winner):
        raise _differs(last, "the final result")
    if chain.hex() != claimed.digest:
        raise _differs(last, "the final digest")
    return Replay(start=first, steps=steps)
