// The options a game is played with, as form controls. One small function per option: given a
// game, it answers null when the option is not the game's, else {label, read} where `label`
// holds the control and `read()` the chosen value as the API's field ({reds: 6}). The choices
// come from the server's protocol module (server/protocol/ids.py), never written here; a new
// option is one function more in `GAME_OPTIONS`.
import {
  RACE_TO_MAX,
  SHOT_CLOCKS,
  SIZED_GAMES,
  SNOOKER_REDS,
  TABLE_SIZE,
  TABLE_SIZES,
  THREE_CUSHION_TARGET,
  THREE_CUSHION_TARGETS,
} from "../net/protocol.js";

function labelled(words, control) {
  const label = document.createElement("label");
  label.append(`${words} `, control);
  return label;
}

/** A select named `name` offering `values` (shown through `words`), `chosen` selected. */
function choice(name, values, chosen, words) {
  const select = document.createElement("select");
  select.name = name;
  for (const value of values) select.append(new Option(words(value), String(value), false, value === chosen));
  return select;
}

/** Race to N racks (frames, games): every game. */
export function raceControl() {
  const input = Object.assign(document.createElement("input"), { type: "number", name: "race_to", min: 1, max: RACE_TO_MAX, value: 1 });
  input.style.width = "4em";
  return { label: labelled("Race to", input), read: () => ({ race_to: Number(input.value) }) };
}

/** Snooker's reds (6, 10 or 15). */
export function redsControl(game) {
  if (game !== "snooker") return null;
  const select = choice("reds", SNOOKER_REDS, Math.max(...SNOOKER_REDS), (n) => `${n} reds`);
  return { label: labelled("Reds", select), read: () => ({ reds: Number(select.value) }) };
}

/** Three-cushion's points to win a game. */
export function targetControl(game) {
  if (game !== "three_cushion") return null;
  const select = choice("target", THREE_CUSHION_TARGETS, THREE_CUSHION_TARGET, (n) => `${n} points`);
  return { label: labelled("Play to", select), read: () => ({ target: Number(select.value) }) };
}

/** Pool's table size in feet (7, 8 or 9). */
export function sizeControl(game) {
  if (!SIZED_GAMES.includes(game)) return null;
  const select = choice("size", TABLE_SIZES, TABLE_SIZE, (feet) => `${feet} ft table`);
  return { label: labelled("Table", select), read: () => ({ size: Number(select.value) }) };
}

/** Seconds per shot (0: no clock). */
export function clockControl() {
  const select = choice("shot_clock", SHOT_CLOCKS, 0, (s) => (s ? `${s} s` : "none"));
  return { label: labelled("Shot clock", select), read: () => ({ shot_clock: Number(select.value) }) };
}

/** The options a game's quick match and bot games are asked with, in the order shown. */
export const GAME_OPTIONS = [raceControl, redsControl, targetControl, sizeControl];
/** ...and a table or challenge made by hand, which also sets its shot clock. */
export const TABLE_OPTIONS = [...GAME_OPTIONS, clockControl];

/** Fill `box` with the controls of `game`'s options among `controls`; answers a function that
 *  reads the chosen options as the API's fields. */
export function optionControls(box, game, controls = GAME_OPTIONS) {
  const made = controls.map((make) => make(game)).filter(Boolean);
  box.replaceChildren(...made.map((c) => c.label));
  return () => Object.assign({}, ...made.map((c) => c.read()));
}

/** The options of a table, challenge or summary in words ("race to 3, 6 reds"); defaults left out. */
export function optionWords(game, options) {
  const words = [];
  if (options.race_to > 1) words.push(`race to ${options.race_to}`);
  if (game === "snooker" && options.reds && options.reds !== Math.max(...SNOOKER_REDS)) words.push(`${options.reds} reds`);
  if (game === "three_cushion") words.push(`to ${options.target || THREE_CUSHION_TARGET} points`);
  if (options.size && options.size !== TABLE_SIZE) words.push(`${options.size} ft table`);
  if (options.shot_clock) words.push(`${options.shot_clock} s shot clock`);
  return words.join(", ");
}
