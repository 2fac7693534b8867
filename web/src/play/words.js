// The referee's decisions and the table's state in words, for the status line (role="status",
// read out by screen readers) and the scoreboard. Names are always set as text, never as HTML.
import { BOTS, CLOCK_PREFIX } from "../net/protocol.js";

/** The referee's choices (`next.options`, and a choice's input `{option}`), the one place
 *  their words are written: the button that makes one, and what the pages say once it is
 *  made (`other`: the name of the player the choice sends back to the table). */
const OPTION_WORDS = {
  play_on: { button: "Play on", chosen: () => "to play on" },
  play_again: { button: "Make them play again", chosen: (other) => `to make ${other} play again` },
  replace: { button: "Replace the balls", chosen: (other) => `to have the balls replaced and ${other} play again` },
};

/** What the referee's `visit` counts in each game. */
const BREAK_WORDS = {
  snooker: "break (points)",
  three_cushion: "run (points)",
  nineball: "run (balls in a visit)",
  eightball: "run (balls in a visit)",
};

export const REGION_WORDS = {
  anywhere: "anywhere",
  kitchen: "behind the head string",
  D: "in the D",
};

/** What one game of a match is called: a snooker frame, a three-cushion game, a pool rack. */
export function rackUnit(game) {
  return game === "snooker" ? "frame" : game === "three_cushion" ? "game" : "rack";
}

/** Whether the referee scores points within a rack (snooker, three-cushion). Pool's
 *  `state.scores` stay 0: a pool player's score is the racks won (the view's `racks_won`). */
export function scoredInPoints(game) {
  return game === "snooker" || game === "three_cushion";
}

/** The label of the button that makes choice `option`. */
export function optionWords(option) {
  return OPTION_WORDS[option]?.button ?? option;
}

/** "the 9", "a red", "the pink", "the cue ball". */
export function ballWords(id) {
  if (id === "cue") return "the cue ball";
  if (/^red\d+$/.test(id)) return "a red";
  return `the ${id}`;
}

function list(items) {
  if (items.length <= 1) return items.join("");
  return `${items.slice(0, -1).join(", ")} and ${items[items.length - 1]}`;
}

/** The server's bots in its words (net/protocol.js): the levels 1 to 5, then the picker. */
export const BOT_LEVELS = Object.fromEntries(
  Object.entries(BOTS)
    .sort(([, a], [, b]) => (a.level || 9) - (b.level || 9))
    .map(([id, { level, name }]) => [id, level ? `${name} bot (level ${level})` : `${name} bot`]),
);
export const DEFAULT_BOT = "bot:3";

export function seatName(view, seat) {
  if (seat == null) return "";
  const player = view.seats[seat];
  // A bot's seat is "bot:" and its chooser (docs/protocol.md): named by its level in words.
  if (player?.id.startsWith("bot:")) return BOT_LEVELS[player.id.slice(4)] ?? player.name;
  return player?.name ?? `Player ${seat + 1}`;
}

/** The name of the referee's player 0 or 1 (its decisions and scores count by player): the
 *  seat's in a match; on a practice table, where one person plays both sides, the person's
 *  name with the side (the scoreboard shows both). */
export function playerName(view, player) {
  return view.mode === "practice" ? `${seatName(view, 0)} (side ${player + 1})` : seatName(view, player);
}

/** Who is credited in a decision: the seat's name, on a practice table the one person. */
function creditedName(view, player) {
  return view.mode === "practice" ? seatName(view, 0) : seatName(view, player);
}

/** The referee's sentences name its players "P1" and "P2": here they name the people. */
export function withNames(view, text) {
  return text.replace(/\bP([12])\b/g, (_, n) => creditedName(view, Number(n) - 1));
}

const sentence = (text) => `${text.charAt(0).toUpperCase()}${text.slice(1)}${/[.!?]$/.test(text) ? "" : "."}`;

/** One decision as sentences: who shot, what fell or scored, fouls, notes, the end of a rack. */
export function decisionWords(view, d) {
  const who = creditedName(view, d.player);
  const out = [];
  const points = d.points.reduce((a, b) => a + b, 0);
  if (view.game === "three_cushion") {
    out.push(points ? `${who} scored ${points === 1 ? "a point" : `${points} points`}.` : `${who} did not score.`);
  } else {
    const potted = d.pocketed.map(ballWords);
    out.push(potted.length ? `${who} potted ${list(potted)}.` : `${who} potted nothing.`);
  }
  // Fouls and notes carry codes (to test and translate) beside their words, shown here.
  for (const foul of d.fouls) out.push(`Foul: ${withNames(view, foul.reason)}.`);
  for (const note of d.notes) out.push(sentence(withNames(view, note.text)));
  if (points && view.game === "snooker") {
    out.push(d.points.map((p, seat) => (p ? `${creditedName(view, seat)} +${p}` : null)).filter(Boolean).join(", ") + ".");
  }
  if (d.over && d.winner != null) out.push(`${creditedName(view, d.winner)} wins the ${rackUnit(view.game)}.`);
  return out.join(" ");
}

/** A choice made by the player in `seat` (a choice has no decision): who chose what. */
export function choiceWords(view, seat, option) {
  const who = creditedName(view, seat);
  const words = OPTION_WORDS[option];
  if (!words) return `${who} chose ${option}.`;
  // On a practice table one person plays both sides: the choice sends back the other side.
  const other = view.mode === "practice" ? "the other side" : seatName(view, 1 - seat);
  return `${who} chose ${words.chosen(other)}.`;
}

/** One input played, {seat, input, decision} (an outcome, a replay's shot): the referee's
 *  decision for a shot, who chose what for a choice. */
export function playedWords(view, played) {
  if (played.decision) return decisionWords(view, played.decision);
  if (played.input?.option) return choiceWords(view, played.seat, played.input.option);
  return "";
}

/** An outcome's words, after why the server played it if it did: the shot id
 *  `clock:<version>` is the input played for a seat whose shot clock ran out (at a match
 *  without one, its turn limit). An input the engine refused (`void`) changed nothing but the
 *  version. */
export function outcomeWords(view, outcome) {
  const limit = clockName(view).toLowerCase();
  const clock = outcome.shot_id?.startsWith(CLOCK_PREFIX) ? `${seatName(view, outcome.seat)}'s ${limit} ran out. ` : "";
  if (outcome.void) return `${clock}The shot could not be played (${outcome.void}).`;
  return clock + playedWords(view, outcome);
}

/** What runs out for the player to act: the table's shot clock, or a match's turn limit. */
export function clockName(view) {
  return view?.options?.shot_clock ? "Shot clock" : "Turn limit";
}

/** Who acts next and how, in words ("Ada to shoot, ball in hand behind the head string."). */
export function nextWords(view) {
  if (view.status === "open") return "Waiting for an opponent.";
  if (view.status === "cancelled") return "This table was cancelled.";
  if (view.status === "over") {
    if (view.mode === "practice") return "Practice over.";
    return view.winner != null ? `Match over: ${seatName(view, view.winner)} wins.` : "Match over.";
  }
  const next = view.next;
  if (!next) return "";
  const who = seatName(view, next.seat);
  if (next.kinds.includes("choice")) return `${who} to choose: ${next.options.map(optionWords).join(" or ")}.`;
  const hand = next.ball_in_hand ? `, ball in hand ${REGION_WORDS[next.ball_in_hand] ?? next.ball_in_hand}` : "";
  return `${who} to shoot${hand}.`;
}

/** What the scoreboard shows beside the referee's player `player`: the points of the rack
 *  (snooker, three-cushion), or in pool the racks won; nothing in pool practice, where no rack
 *  counts for anyone. */
export function seatScore(view, player) {
  if (scoredInPoints(view.game)) return String(view.state.scores[player]);
  return view.mode === "practice" ? "" : String(view.racks_won[player]);
}

/** What the scoreboard's numbers count in `game`, for its tooltip. */
export function scoreUnit(game) {
  return scoredInPoints(game) ? "points in this " + rackUnit(game) : "racks won";
}

/** The racks (frames, games) each player has won, "Frames won: Ada 1, Bob 0.", where they
 *  count: in a match (against a person or the bot), and in a points game only in a race to
 *  more than one (where they are not the score); else "". */
export function racksWonWords(view) {
  if (view.mode === "practice" || (scoredInPoints(view.game) && !(view.options?.race_to > 1))) return "";
  const unit = rackUnit(view.game);
  const won = [0, 1].map((player) => `${playerName(view, player)} ${view.racks_won[player]}`).join(", ");
  return `${unit.charAt(0).toUpperCase()}${unit.slice(1)}s won: ${won}.`;
}

/** The score line: points in the rack (snooker, three-cushion), the racks, frames or games
 *  won, and the current break (the referee's `visit`: snooker's break, three-cushion's run,
 *  pool's balls in one visit). */
export function scoreWords(view) {
  const s = view.state;
  const out = [];
  if (scoredInPoints(view.game)) out.push(`Score (points): ${[0, 1].map((player) => `${playerName(view, player)} ${s.scores[player]}`).join(", ")}.`);
  out.push(racksWonWords(view), `Current ${BREAK_WORDS[view.game]}: ${s.visit}.`);
  if (view.mode === "practice" && Math.max(...s.best) > 0) out.push(`Best ${BREAK_WORDS[view.game]}: ${Math.max(...s.best)}.`);
  return out.filter(Boolean).join(" ");
}
