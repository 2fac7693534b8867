"""The bot's strengths: each level is an execution noise and a search budget.

`hand` is the level's own execution noise (a factor of the tournament noise, rules.bot.noise)
that the bot applies to every shot it sends: a beginner's hand shakes, the strongest level's
does not. The search budget is counted in simulations, never in seconds, so that a decision
is a function of the position, the level and the seed alone (see rules.bot.search):

- pots: how many of the likeliest straight pots are varied in speed and spin;
- screen: how many candidates are simulated once without noise to rank them;
- width, samples: how many of the best screened go on to `samples` noisy simulations each;
- leaders, leader_samples: how many of those get `leader_samples` more, before the best
  mean decides;
- fan_step: three-cushion's spacing (degrees) of the headings tried around each object ball;
- cap: a wall-clock safety limit (s). A search that reaches it stops between stages and plays
  the best shot found so far; that decision, unlike all others, depends on the machine's speed
  (the search reports it). With the budgets below it is not reached on today's engine.

The sample counts are set for the engine's present speed (pure Python: about a millisecond a
plain shot); a faster engine should buy more samples here, in this one table.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True, slots=True)
class Level:
    number: int
    hand: float
    pots: int
    screen: int
    width: int
    samples: int
    leaders: int
    leader_samples: int
    fan_step: float
    cap: float = 60.0

    @property
    def budget(self) -> int:
        """The most simulations one decision may run: a throw correction and a screening run
        for each screened candidate, then the noisy samples."""
        return 2 * self.screen + self.width * self.samples + self.leaders * self.leader_samples


LEVELS: tuple[Level, ...] = (
    Level(
        1,
        hand=3.0,
        pots=2,
        screen=12,
        width=3,
        samples=2,
        leaders=0,
        leader_samples=0,
        fan_step=10.0,
    ),
    Level(
        2,
        hand=2.0,
        pots=3,
        screen=30,
        width=6,
        samples=3,
        leaders=2,
        leader_samples=6,
        fan_step=8.0,
    ),
    Level(
        3,
        hand=1.2,
        pots=4,
        screen=60,
        width=8,
        samples=5,
        leaders=3,
        leader_samples=10,
        fan_step=6.0,
    ),
    Level(
        4,
        hand=0.6,
        pots=5,
        screen=90,
        width=10,
        samples=6,
        leaders=4,
        leader_samples=16,
        fan_step=5.0,
    ),
    Level(
        5,
        hand=0.0,
        pots=6,
        screen=140,
        width=12,
        samples=8,
        leaders=5,
        leader_samples=24,
        fan_step=4.0,
    ),
)
STRONGEST = LEVELS[-1]


def level(number: int) -> Level:
    """The level numbered `number` (1 = beginner ... len(LEVELS) = the strongest)."""
    for lv in LEVELS:
        if lv.number == number:
            return lv
    raise ValueError(f"no bot level {number} (levels: 1 to {len(LEVELS)})")
