"""The bot: a player that searches by simulating candidate shots under execution noise.

- `noise`: the tournament execution-noise model (FastFiz defaults, one factor) and seeded
  error streams.
- `geometry`: straight pots and their estimated chance; `placements`: ball-in-hand places.
- `candidates`: the shots considered; `value`: what an outcome and a position are worth.
- `search`: candidates played under noise through the referee, in budgeted stages, in this
  process or across worker processes.
- `levels`: the strengths (execution noise and search budget); `chooser`: the `Chooser`
  interface, the picker and the bot behind it, built from a name by `chooser`.
- `arena`: whole games between two choosers, and their statistics.
"""
