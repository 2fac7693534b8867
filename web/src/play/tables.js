// Which table the page draws: the server's geometry (GET /web/tables) gives each game's
// standard table, with pool's other sizes beside it (`sizes`), so a 7 ft table is drawn from
// the numbers the engine simulates, never from constants here.

/** The drawable table of `game` at `size` (feet; the game's standard table when absent). */
export function tableFor(tables, game, size) {
  const standard = tables[game];
  return standard.sizes?.[size] ?? standard;
}
