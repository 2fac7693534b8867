// The referee's decisions and the table's state in words, for the status line (role="status",
// read out by screen readers) and the scoreboard. Names are always set as text, never as HTML.
import { BOTS, CLOCK_PREFIX } from "../net/protocol.js";

const OPTION_WORDS = {
  play_on: "Play on",
  play_again: "Make them play again",
  replace: "Replace the balls",
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

export function optionWords(option) {
  return OPTION_WORDS[option] ?? option;
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
  if (d.over && d.winner != null) out.push(`${creditedName(view, d.winner)} wins the ${view.game === "snooker" ? "frame" : "rack"}.`);
  return out.join(" ");
}

/** An outcome's words (its decision's), after why the server played it if it did: the shot id
 *  `clock:<version>` is the stroke played for a seat whose shot clock ran out. */
export function outcomeWords(view, outcome) {
  const clock = outcome.shot_id?.startsWith(CLOCK_PREFIX) ? `${seatName(view, outcome.seat)}'s shot clock ran out. ` : "";
  return clock + decisionWords(view, outcome.decision);
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

/** The score line: racks or frames won, points in the rack, and the current break (the
 *  referee's `visit`: snooker's break, three-cushion's run, pool's balls in one visit). */
export function scoreWords(view) {
  const s = view.state;
  const scores = [0, 1].map((player) => `${playerName(view, player)} ${s.scores[player]}`).join(", ");
  const unit = view.game === "snooker" || view.game === "three_cushion" ? "points" : "racks";
  const race = view.options?.race_to > 1 ? ` Racks won ${view.racks_won.join("-")}.` : "";
  const best = view.mode === "practice" && Math.max(...s.best) > 0 ? ` Best ${BREAK_WORDS[view.game]}: ${Math.max(...s.best)}.` : "";
  return `Score (${unit}): ${scores}. Current ${BREAK_WORDS[view.game]}: ${s.visit}.${best}${race}`;
}
