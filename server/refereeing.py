"""Every call the game service makes into `rules`, in one place: the seam to the referees.

The rest of the server imports the rules' types from here too (`State`, `Decision`,
`PlayerInput`, ...), so a change of the rules' interface is met in this module alone.

The match owner checks an input here on the event loop (cheap: no physics), and the worker
processes run `referee` and `bot_input` (the engine runs there, never on the event loop). What
they return is picklable and already in wire form, so the event loop only stores and publishes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import physics
from rules.bot.chooser import chooser
from rules.codes import RuleError
from rules.game import Setup, play, start
from rules.game import check as rules_check
from rules.inputs import Choice, PlayerInput, Shot, accept
from rules.racks import Game as GameName
from rules.record import GameRecord, replay
from rules.referee import allowed
from rules.referee import referee as referee_of
from rules.spots import in_region, is_free
from rules.state import Decision, Region, State
from server.trajectories import Trajectory, wire_trajectory

#: The seed of the server's bots: their noise draws are keyed by it and by the state.
BOT_SEED = 0
#: Cue speed (m/s) of the stroke played when the shot clock runs out: it rolls about 1 cm.
TIMEOUT_SPEED = 0.05

__all__ = [
    "NOT_REPLAYED",
    "Choice",
    "Decision",
    "GameName",
    "GameRecord",
    "PlayerInput",
    "Refereed",
    "Region",
    "Replayed",
    "RuleError",
    "Shot",
    "State",
    "bot_input",
    "breaker_of",
    "check",
    "constraints",
    "new_rack",
    "referee",
    "replay_record",
    "rule_code",
    "timeout_input",
    "verify",
]


@dataclass(frozen=True, slots=True)
class Refereed:
    """The result of playing one input: the new state, the decision and the motion (shots).

    void: why an accepted input could not be played (the engine refused its scene); the state
    is then unchanged.
    """

    state: State
    decision: Decision | None
    trajectory: Trajectory | None
    void: str | None = None


def breaker_of(game: GameName, breaker: int) -> int:
    """Who really breaks when `breaker` should: in three-cushion each player's cue ball is
    fixed by the rack (the breaker's white), so the rules' player 0 always breaks there."""
    return 0 if game is GameName.THREE_CUSHION else breaker


def rack_setup(game: GameName, seed: int, breaker: int) -> Setup:
    """The rules' setup of a rack whose break goes to seat `breaker` (seats are the referee's
    players, and a setup names its breaker)."""
    return Setup(game=game, seed=seed, breaker=breaker_of(game, breaker))


def new_rack(game: GameName, seed: int, breaker: int) -> State:
    """The opening position of a rack, with `breaker` (a seat) to play the break."""
    return start(rack_setup(game, seed, breaker))


def canonical(action: PlayerInput) -> PlayerInput:
    """The input as the server will play and record it (the rules' canonical form)."""
    return accept(action.model_dump(mode="json"))


def check(state: State, action: PlayerInput) -> None:
    """RuleError if the player to act may not send `action` now (nothing is simulated)."""
    rules_check(state, action)


def rule_code(error: RuleError) -> str | None:
    """The referee's code for a refusal, once the rules give one (None before)."""
    code = getattr(error, "code", None)
    return None if code is None else str(getattr(code, "value", code))


def constraints(state: State) -> tuple[list[str], str, Region | None]:
    """(options pending, cue ball, ball-in-hand region) for the player to act in `state`:
    with options pending the player must choose one, otherwise it shoots."""
    now = allowed(state)
    return list(now.choices), now.cue, now.ball_in_hand


def referee(state: State, action: PlayerInput) -> Refereed:
    """Simulate and judge one checked input (run in a worker process)."""
    try:
        outcome = play(state, action)
    except (RuleError, physics.SceneError, physics.SimulationError) as error:
        return Refereed(state=state, decision=None, trajectory=None, void=str(error))
    trajectory = wire_trajectory(outcome.shot) if outcome.shot else None
    return Refereed(state=outcome.state, decision=outcome.decision, trajectory=trajectory)


def timeout_input(state: State) -> PlayerInput:
    """What the server plays for a player whose shot clock ran out (see server/clock.py).

    A pending choice takes the first option offered; otherwise a dead-slow stroke of the cue
    ball straight away from the nearest ball (placed first, on the first free point of a grid
    over the region, if it is in hand off the table), which the referee rules as a shot that
    hit no ball: a foul in pool and snooker, no point and the turn over in three-cushion.
    """
    if state.pending:
        return Choice(option=state.pending[0])
    referee_ = referee_of(state.game)
    table, cue = referee_.TABLE, referee_.cue_ball(state)
    others = {ball: p for ball, p in state.balls.items() if ball != cue}
    at, place = state.balls.get(cue), None
    if at is None:
        grid = [
            (table.width * i / 8, table.length * j / 32) for j in range(1, 32) for i in range(1, 8)
        ]
        region = state.ball_in_hand or "anywhere"
        at = place = next(
            p for p in grid if in_region(p, region, table) and is_free(p, others, table.R)
        )
    nearest = min(others.values(), key=lambda p: math.dist(p, at))
    heading = math.degrees(math.atan2(at[1] - nearest[1], at[0] - nearest[0])) % 360.0
    strike = {"ball": cue, "speed": TIMEOUT_SPEED, "heading": round(heading, 4)}
    return accept({"strike": strike, "place": place})


def rack_record(setup: Setup, played: list[tuple[PlayerInput, State]]) -> GameRecord:
    """The game record of one rack from each input played and the state it led to: nothing is
    simulated again (the states are the match's own, which a replay of the record recomputes)."""
    record = GameRecord.begin(setup)
    for action, state in played:
        record = record.extend(action, state)
    return record


def best_visits(game: GameName, decisions: list[Decision | None], final: State) -> tuple[int, int]:
    """Each player's best break of a rack: snooker's break and three-cushion's run as the
    referee counts them (`State.best`), pool's balls pocketed in one visit without a foul."""
    if game in ("snooker", "three_cushion"):
        return final.best
    best, visit, visitor = [0, 0], 0, None
    for decision in decisions:
        if decision is None:
            continue
        if decision.player != visitor:
            visit, visitor = 0, decision.player
        visit = 0 if decision.fouls else visit + len(decision.pocketed)
        best[visitor] = max(best[visitor], visit)
        if decision.next_player != visitor or decision.fouls:
            visitor = None
    return best[0], best[1]


@dataclass(frozen=True, slots=True)
class Verified:
    """A replayed record: its game, each player's best break, and its inputs."""

    game: GameName
    best: tuple[int, int]
    inputs: int


#: What replaying a record raises when it does not replay: a refused or differing input
#: (RuleError), or an engine that refuses or abandons one of its shots.
NOT_REPLAYED = (RuleError, physics.SceneError, physics.SimulationError)


def verify(record_json: bytes) -> Verified:
    """Replay and re-referee a submitted record (run in a worker process).

    Raises RuleError for a record that does not replay (an illegal or out-of-bounds input, an
    engine version this server does not run) and ValueError for one that does not parse.
    """
    record = GameRecord.from_json(record_json)
    played = replay(record)
    decisions = [step.decision for step in played.steps]
    best = best_visits(record.setup.game, decisions, played.final)
    return Verified(game=record.setup.game, best=best, inputs=len(record.inputs))


@dataclass(frozen=True, slots=True)
class Replayed:
    """One input of a replayed record: the player who played it, the input, and its result."""

    player: int
    action: PlayerInput
    refereed: Refereed


def replay_record(record: GameRecord) -> list[Replayed]:
    """Every input of a record played again with its motion (run in a worker process).

    The record is replayed and checked as a claim is (`rules.record.replay`), through an engine
    that keeps each shot it simulates: the rules simulate once per shot and never for a
    choice, so the kept shots pair with the record's shots in order. Raises RuleError (and the
    engine's errors) for a record that does not replay.
    """
    shots: list[physics.Shot] = []

    def simulate(scene: physics.Scene) -> physics.Shot:
        shots.append(physics.simulate(scene))
        return shots[-1]

    played = replay(record, simulate)
    motions = iter(shots)
    replayed, before = [], played.start
    for step in played.steps:
        trajectory = wire_trajectory(next(motions)) if isinstance(step.action, Shot) else None
        result = Refereed(state=step.state, decision=step.decision, trajectory=trajectory)
        replayed.append(Replayed(player=before.turn, action=step.action, refereed=result))
        before = step.state
    return replayed


def bot_input(state: State, bot: str) -> PlayerInput:
    """The input of the server's opponent `bot` (a chooser name: "picker" or "bot:N") for the
    player to act (run in a worker process). Its search is seeded by the table's state, so a
    game against it replays."""
    return chooser(bot, BOT_SEED).choose(state)
