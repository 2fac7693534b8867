"""The seam the game service stands on: `check` without simulating, `play` returning the
engine's typed shot beside the decision, everything picklable for worker processes, and one
`Referee` protocol that says what each game allows now."""

from __future__ import annotations

import pickle
from concurrent.futures import ProcessPoolExecutor

import pytest
from pydantic import ValidationError

import physics
from rules.codes import Refusal, RuleError
from rules.game import Outcome, Setup, check, play, start
from rules.inputs import Choice, Shot, Strike
from rules.racks import Game
from rules.referee import REFEREES, Referee, allowed, referee
from rules.state import State, conclude

from .script import hit, pot, rail, refused, scripted, shoot

BREAK = Shot(strike=Strike(ball="cue", speed=8.0, heading=90.0))


def test_play_returns_the_engines_typed_shot_beside_the_decision():
    state = start(Setup(game="nineball", seed=1))
    outcome = play(state, BREAK)
    assert isinstance(outcome, Outcome) and isinstance(outcome.shot, physics.Shot)
    assert outcome.decision is not None and outcome.decision.player == 0
    assert set(outcome.shot.trajectories) == set(state.balls)
    moved = outcome.shot.final["1"].pos
    assert moved is None or tuple(moved) == outcome.state.balls.get("1")
    assert outcome.shot.events[0].type == "strike"


def test_a_choice_has_no_shot():
    state = start(Setup(game="nineball", seed=1)).evolve(shots=2, pending=("play_on",), turn=1)
    outcome = play(state, Choice(option="play_on"), scripted([]))
    assert outcome.shot is None and outcome.decision is None and outcome.state.pending == ()


def test_outcomes_states_inputs_and_refusals_pickle():
    state = start(Setup(game="snooker", seed=2))
    shot = Shot(strike=Strike(ball="cue", speed=2.0, heading=91.0), place=(0.95, 0.7))
    outcome = play(state, shot, scripted([hit("cue", "pink"), rail("pink")]))
    assert outcome.state.retake is not None  # a nested state
    assert pickle.loads(pickle.dumps(outcome)) == outcome
    assert pickle.loads(pickle.dumps(shot)) == shot
    error = pickle.loads(pickle.dumps(RuleError(Refusal.GAME_OVER, "the game is over")))
    assert error.code == Refusal.GAME_OVER and str(error) == "the game is over"


def _play_in_worker(state: State, action: Shot) -> Outcome:
    return play(state, action)


def test_play_runs_in_a_worker_process_and_refusals_come_back_with_their_code():
    state = start(Setup(game="nineball", seed=3))
    with ProcessPoolExecutor(max_workers=1) as pool:
        there = pool.submit(_play_in_worker, state, BREAK).result()
        wrong = Shot(strike=Strike(ball="1", speed=2.0, heading=0.0))
        with refused(Refusal.WRONG_CUE_BALL):
            pool.submit(_play_in_worker, state, wrong).result()
    assert there == play(state, BREAK)  # bit for bit, trajectories included


def never(scene: physics.Scene) -> physics.Shot:
    raise AssertionError("check must not simulate")


@pytest.mark.parametrize(
    ("state", "action", "code"),
    [
        (
            start(Setup(game="nineball", seed=1)).evolve(over=True, winner=0),
            BREAK,
            Refusal.GAME_OVER,
        ),
        (start(Setup(game="nineball", seed=1)), Choice(option="play_on"), Refusal.NOT_AN_OPTION),
        (
            start(Setup(game="nineball", seed=1)).evolve(pending=("play_on",)),
            BREAK,
            Refusal.CHOICE_PENDING,
        ),
        (start(Setup(game="three_cushion", seed=1)), BREAK, Refusal.WRONG_CUE_BALL),
        (
            start(Setup(game="nineball", seed=1)),
            Shot(strike=BREAK.strike, push_out=True),
            Refusal.NO_PUSH_OUT,
        ),
        (
            start(Setup(game="nineball", seed=1)),
            Shot(strike=BREAK.strike, call="top_left"),
            Refusal.NO_CALL,
        ),
        (
            start(Setup(game="snooker", seed=1)),
            Shot(strike=BREAK.strike, nominate="pink"),
            Refusal.BAD_NOMINATION,
        ),
        (
            start(Setup(game="snooker", seed=1)),
            Shot(strike=BREAK.strike, place=(0.889, 0.737)),
            Refusal.PLACE_BLOCKED,
        ),
        (
            start(Setup(game="nineball", seed=1)).evolve(ball_in_hand=None),
            Shot(strike=BREAK.strike, place=(0.5, 0.5)),
            Refusal.NOT_IN_HAND,
        ),
    ],
)
def test_check_refuses_what_play_refuses_without_simulating(state, action, code):
    with refused(code):
        check(state, action)
    with refused(code):
        play(state, action, never)


def test_check_passes_a_legal_input_without_simulating():
    check(start(Setup(game="nineball", seed=1)), BREAK)


def test_every_referee_satisfies_the_protocol():
    assert set(REFEREES) == set(Game)
    for game in Game:
        ref = referee(game)
        assert isinstance(ref, Referee) and game == ref.GAME
        assert ref.new_game(1).game == game


def test_allowed_says_what_each_game_allows_now():
    nine = allowed(start(Setup(game="nineball", seed=1)))
    assert (nine.cue, nine.ball_in_hand, nine.targets, nine.choices) == (
        "cue",
        "kitchen",
        {"1"},
        (),
    )
    assert not nine.options.push_out
    assert allowed(start(Setup(game="nineball", seed=1)).evolve(shots=1)).options.push_out
    eight = State(game="eightball", balls={"cue": (0.5, 0.5), "8": (0.5, 1.5)}, shots=4)
    assert allowed(eight).targets == {"8"} and "top_left" in allowed(eight).options.call
    carom = start(Setup(game="three_cushion", seed=1))
    assert allowed(carom).targets == {"red"} and allowed(carom.evolve(turn=1)).cue == "yellow"
    snooker = start(Setup(game="snooker", seed=1))
    assert allowed(snooker).ball_in_hand == "D" and allowed(snooker).options.nominate == set()
    colour = allowed(snooker.evolve(on="colour"))
    assert colour.options.nominate == {"yellow", "green", "brown", "blue", "pink", "black"}
    free = allowed(snooker.evolve(free_ball=True))
    assert "pink" in free.options.nominate and "red1" not in free.options.nominate


def test_allowed_answers_for_a_finished_game_too():
    for game in Game:
        state = start(Setup(game=game, seed=1))
        empty = state.evolve(balls={}, over=True, winner=0)
        assert allowed(empty).targets == set()  # nothing to hit, and no error


def test_a_push_out_is_offered_then_the_opponent_chooses():
    state, _ = shoot(start(Setup(game="nineball", seed=1)), hit("cue", "1"), pot("2"))
    assert allowed(state).options.push_out
    state, _ = shoot(state, rail("cue"), push_out=True)
    assert allowed(state).choices == ("play_on", "play_again") and allowed(state).player == 1


def test_a_state_update_is_validated():
    state = start(Setup(game="nineball", seed=1))
    with pytest.raises(ValidationError, match="extra"):
        state.evolve(foul_streaks=(1, 0))
    with pytest.raises(ValidationError):
        state.evolve(turn="1")
    with pytest.raises(ValidationError):
        state.evolve(scores=[1, 0])
    with pytest.raises(ValidationError):
        State.model_validate({**state.model_dump(), "ballz": {}})
    with pytest.raises(ValidationError, match="extra"):  # a referee's misspelt game field
        conclude(state, balls=state.balls, next_player=1, free_balls=True)
