// The scoreboard over the status line: each side's name and score (the points of the rack in
// snooker and three-cushion, the racks won in pool), who is to act, the shot
// clock, the options the table is played with ("race to 3, to 5 points"), and what a player of
// each game looks at between shots: eight-ball's groups with the
// balls each has left, snooker's ball on and the points left on the table. All read from the
// server's state; nothing here decides what is legal.
import { optionWords } from "../lib/options.js";
import { nameElement } from "./profile.js";
import { clockName, playerName, racksWonWords, scoredInPoints, scoreUnit, seatScore } from "./words.js";

/** Seconds left on the shot clock from which it is shown in alarm. */
const URGENT_S = 5;
/** Snooker's colours and their values, for the points left on the table. */
const COLOUR_VALUES = { yellow: 2, green: 3, brown: 4, blue: 5, pink: 6, black: 7 };
const GROUP_BALLS = { solids: [1, 2, 3, 4, 5, 6, 7], stripes: [9, 10, 11, 12, 13, 14, 15] };

function span(className, text) {
  return Object.assign(document.createElement("span"), { className, textContent: text });
}

/** Eight-ball: what player `p` is on ("solids, 3 left", "the 8", "open table"). */
function groupWords(state, p) {
  const group = state.groups[p];
  if (!group) return "open table";
  const left = GROUP_BALLS[group].filter((n) => String(n) in state.balls).length;
  return left ? `${group}, ${left} left` : `${group}, on the 8`;
}

/** Snooker: the points still on the table (each red with a black after it, then the colours),
 *  and the ball on in words. */
export function snookerWords(state) {
  const reds = Object.keys(state.balls).filter((b) => b.startsWith("red")).length;
  const colours = Object.keys(COLOUR_VALUES).filter((c) => c in state.balls);
  const left = reds * 8 + colours.reduce((sum, c) => sum + COLOUR_VALUES[c], 0) + (state.on === "colour" ? 7 : 0);
  const on = state.free_ball ? "a free ball" : state.on === "red" ? "a red" : state.on === "colour" ? "a colour" : `the ${state.on}`;
  return `Ball on: ${on}. Points remaining: ${left}.`;
}

/** Fill `box` with the scoreboard of table view `v`. */
export function showScoreboard(box, v) {
  box.replaceChildren();
  for (const seat of [0, 1]) {
    const acting = v.status === "playing" && (v.mode === "practice" ? v.state.turn : v.next?.seat) === seat;
    const gone = v.presence?.[seat] === false && v.seats[seat] ? " (disconnected)" : "";
    const name = span(`name${acting ? " to-act" : ""}`, "");
    const player = v.seats[v.mode === "practice" ? 0 : seat]; // practice: one person, both sides
    name.append(nameElement(player, player ? playerName(v, seat) : "(open seat)"), gone);
    if (v.game === "eightball") name.append(span("group muted", ` ${groupWords(v.state, seat)}`));
    const score = span("score", seatScore(v, seat));
    score.title = scoreUnit(v.game);
    box.append(name, score);
  }
  const options = optionWords(v.game, v.options ?? {});
  if (options) box.append(span("table-info options-words", `${options.charAt(0).toUpperCase()}${options.slice(1)}.`));
  // Snooker's and three-cushion's scores are the rack's points: the frames (games) won too.
  const won = scoredInPoints(v.game) ? racksWonWords(v) : "";
  if (won) box.append(span("table-info racks-won", won));
  if (v.game === "snooker") box.append(span("table-info", snookerWords(v.state)));
  const clock = span("clock", "");
  clock.id = "clock";
  box.append(clock);
  showClock(v);
}

/** The seconds left to the player to act (the server rules the deadline; this only shows it). */
export function showClock(v) {
  const clock = document.getElementById("clock");
  const deadline = v?.next?.deadline;
  if (!clock) return;
  const left = deadline ? Math.max(0, Math.ceil(deadline - Date.now() / 1000)) : null;
  clock.textContent = left === null ? "" : `${clockName(v)} ${left} s`;
  clock.classList.toggle("urgent", left !== null && left <= URGENT_S);
}
