"""Every call the game service makes into `rules`, in one place: the seam to the referees.

The rest of the server imports the rules' types from here too (`State`, `Decision`,
`PlayerInput`, ...), so a change of the rules' interface is met in this module alone.

The table actor checks an input here on the event loop (cheap: no physics), and the worker
processes run `referee` and `bot_input` (the engine runs there, never on the event loop). What
they return is picklable and already in wire form, so the event loop only stores and publishes.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, replace

import physics
from rules.bot.chooser import chooser
from rules.codes import Refusal, RuleError
from rules.compact import decode_position, encode_position
from rules.game import Setup, play, start
from rules.game import check as rules_check
from rules.inputs import Choice, Option, PlayerInput, Shot, accept
from rules.positions import ball_names, check_position, check_start
from rules.positions import presets as named_positions
from rules.racks import REDS_FULL
from rules.racks import Game as GameName
from rules.record import GameRecord, replay
from rules.referee import allowed, table_of
from rules.referee import referee as referee_of
from rules.spots import STANDARD_SIZE, Point, free_place
from rules.state import Decision, Region, State
from rules.three_cushion import DEFAULT_TARGET
from server.game import visits
from server.protocol.models import TableOptions
from server.protocol.trajectories import Trajectory, wire_trajectory

#: The rules' code of a set-up position that cannot start a rack.
BAD_POSITION = Refusal.BAD_POSITION.value
#: A set-up position: ball id -> where it lies.
Position = dict[str, Point]
#: The options of a table created without any (a standard rack of each game).
DEFAULT_OPTIONS = TableOptions()

#: The seed of the server's bots: their noise draws are keyed by it and by the state.
BOT_SEED = 0
#: Cue speed (m/s) of the stroke played when the shot clock runs out: it rolls about 1 cm.
TIMEOUT_SPEED = 0.05

__all__ = [
    "BAD_POSITION",
    "DEFAULT_TARGET",
    "NOT_REPLAYED",
    "REDS_FULL",
    "STANDARD_SIZE",
    "Choice",
    "Decision",
    "GameName",
    "GameRecord",
    "Next",
    "Option",
    "PlayerInput",
    "Position",
    "Refereed",
    "Region",
    "Replayed",
    "RuleError",
    "Setup",
    "Shot",
    "State",
    "ball_set",
    "bot_input",
    "check",
    "checked_position",
    "choices",
    "constraints",
    "new_rack",
    "next_breaker",
    "presets",
    "referee",
    "referee_for_table",
    "replay_record",
    "rule_code",
    "share_code",
    "shared",
    "shot_position",
    "start",
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
    #: The trajectory's JSON, encoded where it was simulated (the worker), which the server
    #: writes into the outcome it publishes and stores (server.protocol.encoding).
    trajectory_json: bytes | None = None


def next_breaker(game: GameName, breaker: int) -> int:
    """Who breaks the rack after one `breaker` broke: the other player, except in
    three-cushion, where each player's cue ball is fixed by the rack (the breaker's white), so
    the rules' player 0 always breaks. The one place a match's breaks are mapped."""
    return 0 if game is GameName.THREE_CUSHION else 1 - breaker


def rack_setup(
    game: GameName,
    options: TableOptions,
    seed: int,
    breaker: int,
    position: Position | None = None,
) -> Setup:
    """The rules' setup of a rack whose break goes to seat `breaker` (seats are the referee's
    players, and a setup names its breaker; seed: the table's seed plus the rack's number), at
    the table's `options` that shape a rack (snooker's reds, three-cushion's target, pool's
    table size), from a set-up `position` (checked: `checked_position`) or the game's own
    rack."""
    return Setup(
        game=game,
        seed=seed,
        breaker=breaker,
        reds=options.reds,
        target=options.target,
        size=options.size,
        position=position,
    )


def new_rack(
    game: GameName, seed: int, breaker: int, options: TableOptions = DEFAULT_OPTIONS
) -> State:
    """The opening position of a rack, with `breaker` (a seat) to play the break."""
    return start(rack_setup(game, options, seed, breaker))


def checked_position(
    game: GameName, position: Position, options: TableOptions, left: bool = False
) -> Position:
    """A set-up position as the rules start it: a player's, on the bed and apart, in canonical
    steps; or (`left`) one a shot left, where the engine lets balls rest, to the bit
    (`rules.positions`). RuleError (BAD_POSITION) naming what is wrong when it cannot start a
    rack of `game` at these options."""
    check = check_start if left else check_position
    return check(game, position, options.size, options.reds)


@functools.cache
def ball_set(game: GameName, reds: int = REDS_FULL) -> tuple[str, ...]:
    """The balls a set-up position of `game` (snooker with `reds`) may hold."""
    return ball_names(game, reds)


@functools.cache
def presets(game: GameName, size: int = STANDARD_SIZE) -> dict[str, Position]:
    """The named practice positions of `game` on its `size` table (`rules.positions`)."""
    return named_positions(game, size)


def shot_position(state: State, action: PlayerInput) -> Position:
    """The balls as they stood when `action` (a shot played in `state`) struck: the table and
    any cue ball placed in hand; the balls of `state` for a choice."""
    balls = dict(state.balls)
    if isinstance(action, Shot) and action.place is not None:
        balls[allowed(state).cue] = action.place
    return balls


def share_code(setup: Setup) -> str:
    """The compact share-link code of a setup's position (`rules.compact`)."""
    return encode_position(setup)


def shared(code: str) -> Setup:
    """The setup of a shared position's code; RuleError (MALFORMED, BAD_POSITION) otherwise."""
    return decode_position(code)


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


@dataclass(frozen=True, slots=True)
class Next:
    """What the player to act in a state must or may send, as its referee allows it
    (`rules.referee.allowed`), in the order the wire shows it.

    choices: when not empty, the player must send one of these and cannot shoot. Otherwise a
    shot: of the `cue` ball, placed in `ball_in_hand` if given (required when `place_required`:
    the cue ball is off the table), first hitting one of `targets`; it may declare a push-out
    if `push_out`, must call one of `call` when that is not empty (and nothing otherwise), and
    may nominate one of `nominate`.
    """

    choices: tuple[Option, ...]
    cue: str
    ball_in_hand: Region | None
    place_required: bool
    targets: tuple[str, ...]
    push_out: bool
    call: tuple[str, ...]
    nominate: tuple[str, ...]


def choices(state: State) -> tuple[Option, ...]:
    """`constraints(state).choices` without working out the rest (the targets, the cue
    ball, the options of a shot): the table actor asks it of every input it checks."""
    return state.pending


def constraints(state: State) -> Next:
    """What the player to act in `state` must or may send next (see `Next`)."""
    now = allowed(state)
    return Next(
        choices=now.choices,
        cue=now.cue,
        ball_in_hand=now.ball_in_hand,
        place_required=now.cue not in state.balls,
        targets=tuple(sorted(now.targets)),
        push_out=now.options.push_out,
        call=now.options.call,
        nominate=tuple(sorted(now.options.nominate)),
    )


def referee(state: State, action: PlayerInput) -> Refereed:
    """Simulate and judge one checked input (run in a worker process)."""
    try:
        outcome = play(state, action)
    except (RuleError, physics.SceneError, physics.SimulationError) as error:
        return Refereed(state=state, decision=None, trajectory=None, void=str(error))
    trajectory = wire_trajectory(outcome.shot) if outcome.shot else None
    encoded = None if trajectory is None else Trajectory.__pydantic_serializer__.to_json(trajectory)
    return Refereed(outcome.state, outcome.decision, trajectory, trajectory_json=encoded)


def referee_for_table(state: State, action: PlayerInput) -> Refereed:
    """`referee` as a table's worker answers it: the motion as its JSON alone
    (`trajectory_json`, with `trajectory` None). A table only writes the motion into the
    outcome it stores and publishes, never reads it; unpickled as models in the server, it
    was two thirds of the worker's answer's cost there (80 of 115 us a shot of the server's
    CPU in bench/match_load.py, its objects' garbage collection included)."""
    return replace(referee(state, action), trajectory=None)


def timeout_input(state: State) -> PlayerInput:
    """What the server plays for a player whose shot clock ran out (see server/game/clock.py).

    A pending choice takes the first option offered; otherwise a dead-slow stroke of the cue
    ball straight away from the nearest ball (placed first, where `rules.spots.free_place`
    finds room in the region, if it is in hand off the table), which the referee rules as a
    shot that hit no ball: a foul in pool and snooker, no point and the turn over in
    three-cushion.
    """
    if state.pending:
        return Choice(option=state.pending[0])
    referee_ = referee_of(state.game)
    table, cue = table_of(state), referee_.cue_ball(state)
    others = {ball: p for ball, p in state.balls.items() if ball != cue}
    at, place = state.balls.get(cue), None
    if at is None:
        place = free_place(state.ball_in_hand or "anywhere", others, table)
        if place is None:  # a set-up position leaves room (rules.positions); play cannot fill it
            raise RuleError(Refusal.PLACE_BLOCKED, "no room to place the cue ball in hand")
        at = place
    nearest = min(others.values(), key=lambda p: math.dist(p, at))
    heading = math.degrees(math.atan2(at[1] - nearest[1], at[0] - nearest[0])) % 360.0
    strike = {"ball": cue, "speed": TIMEOUT_SPEED, "heading": round(heading, 4)}
    calls = referee_.options(state).call  # eight-ball on the 8: a pocket must be called
    return accept({"strike": strike, "place": place, "call": calls[0] if calls else None})


def rack_record(setup: Setup, played: list[tuple[PlayerInput, State]]) -> GameRecord:
    """The game record of one rack from each input played and the state it led to: nothing is
    simulated again (the states are the match's own, which a replay of the record recomputes)."""
    record = GameRecord.begin(setup)
    for action, state in played:
        record = record.extend(action, state)
    return record


@dataclass(frozen=True, slots=True)
class RackArchive:
    """What a finished (or abandoned) rack is archived with: its game record, each player's
    best break in it (the last state's `best`) and each best break's identity
    (`server.game.visits`, None for a player who scored none)."""

    record: GameRecord
    best: tuple[int, int]
    keys: tuple[str | None, str | None]


def rack_archive(setup: Setup, played: list[tuple[PlayerInput, State]]) -> RackArchive:
    """The archive of a rack from each input played and the state it led to (run in a worker
    process: the record's chain hashes every state and the break keys every visit's inputs,
    some 40 us an input, a nine-ball rack's half a millisecond and a long snooker frame's
    several, which on the event loop would hold up every other table meanwhile)."""
    keys = visits.break_keys(setup.game, start(setup), played)
    return RackArchive(rack_record(setup, played), played[-1][1].best, keys)


@dataclass(frozen=True, slots=True)
class Verified:
    """A replayed record: its game, each player's best break (the referee's `State.best`:
    snooker's break, three-cushion's run, pool's balls pocketed in one visit without a foul),
    its inputs, and the identity of each player's best break (`server.game.visits`: the
    position and inputs of the visit, None when the player scored no break)."""

    game: GameName
    best: tuple[int, int]
    inputs: int
    keys: tuple[str | None, str | None] = (None, None)


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
    steps = [(step.action, step.state) for step in played.steps]
    return Verified(
        game=record.setup.game,
        best=played.final.best,
        inputs=len(record.inputs),
        keys=visits.break_keys(record.setup.game, played.start, steps),
    )


@dataclass(frozen=True, slots=True)
class Replayed:
    """One input of a replayed record: the player who played it, the input, and its result."""

    player: int
    action: PlayerInput
    refereed: Refereed


def replay_record(record: GameRecord, window: range | None = None) -> list[Replayed]:
    """The inputs of a record in `window` (indexes; None: all) played again with their motion
    (run in a worker process).

    The record is replayed and checked as a claim is (`rules.record.replay`), up to the end of
    the window, through an engine that keeps the shots it simulates within it: the rules
    simulate once per shot and never for a choice, so the kept shots pair with the window's
    shots in order. Only the window's motions are held, so a long record costs the memory of
    the inputs asked for (before, a 5,000-input record held 0.85 GB). Raises RuleError (and
    the engine's errors) for a record that does not replay.
    """
    inputs = record.inputs
    window = range(len(inputs)) if window is None else window
    shots_before = sum(isinstance(action, Shot) for action in inputs[: window.start])
    shots: list[physics.Shot] = []
    simulated = 0

    def simulate(scene: physics.Scene) -> physics.Shot:
        nonlocal simulated
        shot = physics.simulate(scene)
        simulated += 1
        if simulated > shots_before:
            shots.append(shot)
        return shot

    played = replay(record, simulate, until=window.stop)
    motions = iter(shots)
    replayed = []
    for n in window:
        if n >= len(played.steps):
            break
        step, before = played.steps[n], played.steps[n - 1].state if n else played.start
        trajectory = wire_trajectory(next(motions)) if isinstance(step.action, Shot) else None
        result = Refereed(state=step.state, decision=step.decision, trajectory=trajectory)
        replayed.append(Replayed(player=before.turn, action=step.action, refereed=result))
    return replayed


def bot_input(state: State, bot: str) -> PlayerInput:
    """The input of the server's opponent `bot` (a chooser name: "picker" or "bot:N") for the
    player to act (run in a worker process). Its search is seeded by the table's state, so a
    game against it replays."""
    return chooser(bot, BOT_SEED).choose(state)
