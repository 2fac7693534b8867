"""Referees and racks for nine-ball, eight-ball, snooker and three-cushion billiards.

Pure functions and pydantic models, no I/O (except the command line in `rules.cli`):

- `racks`: the `Game` names and the standard starting layouts, placed from a seed.
- `spots`: the marked spots and regions of each table, and free-place searches for respots.
- `inputs`: what a player sends (a shot with its pre-shot choices, or a choice after a foul),
  canonical and quantised; `accept` is the entry point for input from outside.
- `codes`: the codes of refusals (`RuleError`), fouls and notes.
- `state`: the state before a shot and the referee's `Decision`.
- `events`: what the referees read from the physics engine's typed result.
- `nineball`, `eightball`, `snooker`, `three_cushion`: one referee per game (each module's
  docstring lists the rule set chosen and what is left out); `pool` holds what the two pool
  games share, `aim` the straight-line geometry of "snookered".
- `referee`: the `Referee` protocol the four modules satisfy, the lookup from a game to its
  referee, and `allowed`: what the player to act may do now.
- `game`: the seam over the four referees: start a game, `check` an input, `play` it.
- `record`: a game as data (engine, setup, inputs, digests, result) and `replay`, which
  rebuilds every state and refuses a record that is not the game it states; `compact`: its
  share-link form; `tamper`: alterations to try a verifier with.
- `pickers`, `selfplay`: simple players for whole games; `cli`: `billiards selfplay|replay`.
"""
