"""A long, standard game record for the claim benches: `python bench/long_record.py OUT [N]`.

The shot pickers finish a game in a few dozen inputs, but a claim's cost grows with its
record's length, and a hostile claimant sends the longest it can. Three-cushion has no foul
limit, so this plays N soft shots in turn (each from where the balls lie, turning a few
degrees every time; a soft shot seldom makes a point), then lets the rules' shot picker play
until the record holds a break of at least one point, and writes the record (JSON).
"""

from __future__ import annotations

import sys

from rules.bot.chooser import chooser
from rules.game import Setup, play, start
from rules.inputs import Shot, Strike
from rules.record import GameRecord

SOFT_SPEED = 1.5


def long_record(inputs: int, seed: int = 1) -> GameRecord:
    setup = Setup(game="three_cushion", seed=seed)
    state = start(setup)
    record = GameRecord.begin(setup, state)
    for n in range(inputs):
        ball = "white" if state.turn == 0 else "yellow"
        action = Shot(strike=Strike(ball=ball, speed=SOFT_SPEED, heading=(37.0 * n) % 360))
        state = play(state, action).state
        record = record.extend(action, state)
    picker = chooser("picker", seed)
    while max(state.best) < 1 and not state.over:
        action = picker.choose(state)
        state = play(state, action).state
        record = record.extend(action, state)
    return record


if __name__ == "__main__":
    count = int(sys.argv[2]) if len(sys.argv) > 2 else 2000
    made = long_record(count)
    with open(sys.argv[1], "w") as out:
        out.write(made.to_json())
    print(f"{len(made.inputs)} inputs, final scores {made.final.scores}")
