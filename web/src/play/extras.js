// What a shot may carry beside the stroke: nine-ball's push-out (the shot after the break),
// eight-ball's called pocket for the 8, snooker's nominated ball (a free ball, or the colour
// after a red). The referee checks them; these widgets only offer them when they can apply.
// (The table's constraints do not say which of them the next shot needs, so the eight-ball
// test "on the 8" mirrors the referee's: no ball of the player's group, or of either group
// on an open table, is left.)

const POCKETS = ["bottom_left", "bottom_right", "middle_left", "middle_right", "top_left", "top_right"];
const COLOURS = ["yellow", "green", "brown", "blue", "pink", "black"];

const words = (name) => name.replace("_", " ");

function group(id) {
  const n = Number(id);
  return n >= 1 && n <= 7 ? "solids" : n >= 9 && n <= 15 ? "stripes" : null;
}

function onTheEight(state) {
  if (state.shots === 0) return false;
  const mine = state.groups[state.turn];
  return !Object.keys(state.balls).some((b) => group(b) && (mine === null || group(b) === mine));
}

function select(name, label, options, blank, required = false) {
  const wrap = document.createElement("label");
  wrap.textContent = `${label} `;
  const el = document.createElement("select");
  el.name = name;
  el.required = required;
  if (blank) el.append(new Option(blank, ""));
  for (const o of options) el.append(new Option(words(o), o));
  wrap.append(el);
  return wrap;
}

/** Offer the extras that can apply to the next shot of table view `v` (null: none). */
export function showExtras(box, v) {
  const items = [];
  if (v?.game === "nineball" && v.state.shots === 1) {
    const wrap = document.createElement("label");
    const box_ = Object.assign(document.createElement("input"), { type: "checkbox", name: "push_out" });
    wrap.append(box_, document.createTextNode(" Push out"));
    items.push(wrap);
  }
  if (v?.game === "eightball" && onTheEight(v.state)) {
    items.push(select("call", "Pocket for the 8", POCKETS, "(call a pocket)", true));
  }
  if (v?.game === "snooker" && (v.state.free_ball || v.state.on === "colour")) {
    const balls = v.state.free_ball ? Object.keys(v.state.balls).filter((b) => b !== "cue") : COLOURS.filter((c) => c in v.state.balls);
    items.push(select("nominate", v.state.free_ball ? "Free ball" : "Nominate", balls, "(the first ball hit)"));
  }
  box.replaceChildren(...items);
}

/** The first extra the shot needs but has not been given ({input, words}), or null. */
export function missingExtra(box) {
  const input = [...box.querySelectorAll("select")].find((el) => el.required && !el.value);
  return input ? { input, words: `${input.parentElement.firstChild.textContent.trim()}: choose one before the shot.` } : null;
}

/** The extras chosen, as fields of the shot. */
export function readExtras(box) {
  const out = {};
  const push = box.querySelector('input[name="push_out"]');
  if (push?.checked) out.push_out = true;
  for (const name of ["call", "nominate"]) {
    const el = box.querySelector(`select[name="${name}"]`);
    if (el?.value) out[name] = el.value;
  }
  return out;
}
