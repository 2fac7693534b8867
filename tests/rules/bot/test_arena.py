"""The arena: alternating breaks, the table's noise on every shot, reproducible summaries,
and the `billiards arena` command."""

from __future__ import annotations

import json
from collections import Counter

from rules.bot.arena import arena, wilson
from rules.bot.chooser import Picker, chooser
from rules.bot.levels import level
from rules.bot.noise import tournament
from rules.inputs import PlayerInput
from rules.racks import Game
from rules.state import State
from server.cli import main


class Recording(Picker):
    """The picker, noting the seat it played each break from and every input it sent."""

    def __init__(self, name: str) -> None:
        super().__init__()
        self.name = name
        self.breaks: list[int] = []
        self.sent: list[PlayerInput] = []

    def choose(self, state: State) -> PlayerInput:
        if state.shots == 0:
            self.breaks.append(state.turn)
        action = super().choose(state)
        self.sent.append(action)
        return action


def timeless(side: dict) -> dict:
    return {k: v for k, v in side.items() if not k.startswith("decision_")}


def test_breaks_alternate_and_results_add_up():
    a, b = Recording("a"), Recording("b")
    result = arena(Game.NINEBALL, a, b, 4, seed=1, noise=tournament(1.0))
    assert a.breaks == [0, 0] and b.breaks == [0, 0]  # each broke from seat 0, in turn
    assert result["a"]["wins"] + result["b"]["wins"] + result["unfinished"] == 4
    assert result["a"]["decisions"] == len(a.sent)


def test_each_game_says_why_its_loser_lost():
    """The progress callback gets each game's loss, and the losses tally the side's counts."""
    results = []
    summary = arena(
        Game.NINEBALL,
        Picker(),
        Picker(),
        6,
        seed=3,
        noise=tournament(1.0),
        progress=lambda i, game, sa, sb: results.append((i, game)),
    )
    tallied: Counter[tuple[str, str]] = Counter()
    for i, game in results:
        if game.winner is None:
            assert game.loss is None
            continue
        a_lost = game.winner == 1 - i % 2  # a holds seat 0 in the even-numbered games
        tallied[("a" if a_lost else "b", str(game.loss))] += 1
    assert tallied  # some game ended
    for side in ("a", "b"):
        counts = {why: n for (s, why), n in tallied.items() if s == side}
        assert counts == summary[side]["losses"]


def test_the_same_seed_replays_the_same_arena():
    runs = [
        arena(Game.EIGHTBALL, Picker(), Picker(), 2, seed=5, noise=tournament(1.0))
        for _ in range(2)
    ]
    assert timeless(runs[0]["a"]) == timeless(runs[1]["a"])
    assert timeless(runs[0]["b"]) == timeless(runs[1]["b"])


def test_the_table_noise_moves_every_shot_but_not_without_noise():
    quiet, loud = Recording("q"), Recording("l")
    calm = arena(Game.NINEBALL, quiet, Picker(), 1, seed=2, noise=tournament(0.0), max_inputs=3)
    arena(Game.NINEBALL, loud, Picker(), 1, seed=2, noise=tournament(1.0), max_inputs=3)
    assert quiet.sent[0] == loud.sent[0]  # the same break is sent...
    assert calm["a"]["decisions"] >= 1
    # ...and the game that follows differs, because the table moved the break.
    assert quiet.sent[1:] != loud.sent[1:]


def test_wilson_interval():
    lo, hi = wilson(9, 10)
    assert 0 < lo < 0.9 < hi <= 1
    lo2, hi2 = wilson(90, 100)
    assert lo < lo2 < 0.9 < hi2 < hi
    assert wilson(0, 0) == (0.0, 1.0)


def test_the_arena_command_prints_json(capsys):
    code = main(["arena", "nineball", "--a", "picker", "--b", "picker", "--games", "2", "--json"])
    assert code == 0
    out = json.loads(capsys.readouterr().out)
    assert out["games"] == 2
    for side in ("a", "b"):
        assert set(out[side]) >= {"wins", "ci95", "per_visit", "run_outs", "highest"}
        assert out[side]["decision_p95_s"] >= 0


def test_the_arena_command_refuses_an_unknown_chooser(capsys):
    assert main(["arena", "nineball", "--a", "robot", "--games", "1"]) == 2
    assert "robot" in capsys.readouterr().err


def test_a_bots_simulations_are_counted():
    bot = chooser("bot:1", seed=3)
    result = arena(Game.NINEBALL, bot, Picker(), 1, seed=4, noise=tournament(1.0), max_inputs=6)
    assert 0 < result["a"]["simulations_mean"] <= level(1).budget
    assert result["b"]["simulations_mean"] == 0.0
