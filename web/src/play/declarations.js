// What a shot declares beside its stroke: nine-ball's push-out, eight-ball's called pocket for
// the 8, snooker's nominated ball. Which of them the next shot may or must carry is the
// server's `next.shot` (ShotRules: `push_out`, `call`, `nominate`); these widgets only offer
// what it lists, so the browser decides no rule.

const words = (name) => name.replaceAll("_", " ");

function select(name, label, options, blank, required) {
  const wrap = document.createElement("label");
  wrap.textContent = `${label} `;
  const el = document.createElement("select");
  el.name = name;
  el.required = required;
  el.append(new Option(blank, ""));
  for (const o of options) el.append(new Option(words(o), o));
  wrap.append(el);
  return wrap;
}

/** Offer the declarations ShotRules `shot` allows (null: none, not the player's shot). */
export function showDeclarations(box, shot) {
  const items = [];
  if (shot?.push_out) {
    const wrap = document.createElement("label");
    const input = Object.assign(document.createElement("input"), { type: "checkbox", name: "push_out" });
    wrap.append(input, document.createTextNode(" Push out"));
    items.push(wrap);
  }
  // A non-empty `call` means a called pocket is required.
  if (shot?.call?.length) items.push(select("call", "Pocket for the 8", shot.call, "(call a pocket)", true));
  if (shot?.nominate?.length) items.push(select("nominate", "Nominate", shot.nominate, "(the first ball hit)", false));
  box.replaceChildren(...items);
}

/** The first declaration the shot needs but has not been given ({input, words}), or null. */
export function missingDeclaration(box) {
  const input = [...box.querySelectorAll("select")].find((el) => el.required && !el.value);
  return input ? { input, words: `${input.parentElement.firstChild.textContent.trim()}: choose one before the shot.` } : null;
}

/** The declarations chosen, as fields of the shot. */
export function readDeclarations(box) {
  const out = {};
  if (box.querySelector('input[name="push_out"]')?.checked) out.push_out = true;
  for (const name of ["call", "nominate"]) {
    const el = box.querySelector(`select[name="${name}"]`);
    if (el?.value) out[name] = el.value;
  }
  return out;
}
