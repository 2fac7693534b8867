// The referee's decisions and the table's state in words, for the status line (role="status",
// read out by screen readers) and the scoreboard. Names are always set as text, never as HTML.
import { CLOCK_PREFIX } from "../net/protocol.js";

const OPTION_WORDS = {
  play_on: "Play on",
  play_again: "Make them play again",
  replace: "Replace the balls",
};

const REGION_WORDS = {
  anywhere: "anywhere",
  kitchen: "behind the head string",
  D: "in the D",
};

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

export function seatName(view, seat) {
  if (seat == null) return "";
  return view.seats[seat]?.name ?? `Player ${seat + 1}`;
}

/** The name of the referee's player 0 or 1 (its decisions and scores count by player): the
 *  seat's in a match; on a practice table, where seat 0 plays both sides, "P1" or "P2". */
export function playerName(view, player) {
  return view.mode === "practice" ? `P${player + 1}` : seatName(view, player);
}

/** One decision as sentences: who shot, what fell, fouls, notes, the end of a rack or match. */
export function decisionWords(view, d) {
  const who = view.mode === "practice" ? seatName(view, 0) : seatName(view, d.player);
  const out = [];
  const potted = d.pocketed.map(ballWords);
  out.push(potted.length ? `${who} potted ${list(potted)}.` : `${who} potted nothing.`);
  // Fouls and notes carry codes (to test and translate) beside their words, shown here.
  for (const foul of d.fouls) out.push(`Foul: ${foul.reason}.`);
  for (const note of d.notes) out.push(`${note.text.charAt(0).toUpperCase()}${note.text.slice(1)}.`);
  const points = d.points.reduce((a, b) => a + b, 0);
  if (points && view.game !== "nineball" && view.game !== "eightball") {
    out.push(d.points.map((p, seat) => (p ? `${playerName(view, seat)} +${p}` : null)).filter(Boolean).join(", ") + ".");
  }
  if (d.over && d.winner != null) out.push(`${playerName(view, d.winner)} wins the ${view.game === "snooker" ? "frame" : "rack"}.`);
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
  const best = view.mode === "practice" && Math.max(...s.best) > 0 ? ` Best break: ${Math.max(...s.best)}.` : "";
  return `Score (${unit}): ${scores}. Break: ${s.visit}.${best}${race}`;
}
