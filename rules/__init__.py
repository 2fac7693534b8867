"""Referees and racks for nine-ball, eight-ball, snooker and three-cushion billiards.

Pure functions and pydantic models, no I/O (except the command line in `rules.cli`):

- `racks`: the standard starting layouts, placed from a seed.
- `spots`: the marked spots and regions of each table, and free-place searches for respots.
- `inputs`: what a player sends (a shot with its pre-shot choices, or a choice after a foul).
- `state`: the state before a shot, the referee's `Decision`, and `RuleError`.
- `events`: what the referees read from the physics engine's event list.
- `nineball`, `eightball`, `snooker`, `three_cushion`: one referee per game (each module's
  docstring lists the rule set chosen and what is left out); `pool` holds what the two pool
  games share, `aim` the straight-line geometry of "snookered".
- `game`: one interface over the four referees: check an input, simulate it, judge it.
- `record`: a game as data (setup + inputs) and `replay`, which rebuilds every state.
- `pickers`, `selfplay`: simple players for whole games; `cli`: `billiards selfplay|replay`.
"""
