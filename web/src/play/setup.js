// The practice table as a practice tool (/practice/{game}): set up any position by dragging
// balls on and off the table, or one of the game's named positions; re-rack; take the last
// shot again from the same position; share a position as a link, which sets it up when opened.
// The server checks every position (the game's own balls, on the bed, none overlapping, none
// in a pocket) and sends the balls a position may hold and the named positions
// (view.ball_set, view.presets); the page only keeps a drag from leaving a ball where the
// server would refuse it, and says the server's words when it refuses.
import { ApiError, get, post } from "../net/api.js";
import { POSITION_PARAM } from "../net/protocol.js";
import { hooks } from "./hooks.js";
import { freePlace, overlap } from "./placing.js";

const PRESET_WORDS = { combination: "Frozen-ball combination", long_pot: "Long pot", standard: "Three-cushion standard" };

function button(label, onClick, attrs = {}) {
  const b = Object.assign(document.createElement("button"), { type: "button", textContent: label, ...attrs });
  b.addEventListener("click", onClick);
  return b;
}

/** The id of this player's practice table for `game`: a new one set up from the shared
 *  position in the address (`?position=`, checked by the server), else the one kept from last
 *  time if it still runs, else a new one. */
export async function practiceTable(game, me) {
  const key = `billiards.practice.${game}`;
  const code = new URLSearchParams(location.search).get(POSITION_PARAM);
  if (code) {
    let shared;
    try {
      shared = await get(`/api/positions/${encodeURIComponent(code)}`);
    } catch (e) {
      throw new Error(`this shared position cannot be set up (${e.code ?? "error"}: ${e.message})`);
    }
    const { size, reds, position } = shared;
    const view = await post("/api/tables", { game: shared.game, mode: "practice", size, reds, position });
    localStorage.setItem(key, view.id);
    history.replaceState(null, "", location.pathname);
    return view.id;
  }
  const kept = localStorage.getItem(key);
  if (kept) {
    try {
      const view = await get(`/api/tables/${kept}`);
      if (view.status === "playing" && view.seats[0]?.id === me.id) return kept;
    } catch (e) {
      if (!(e instanceof ApiError)) throw e;
    }
  }
  const view = await post("/api/tables", { game, mode: "practice" });
  localStorage.setItem(key, view.id);
  return view.id;
}

/** The practice panel of a play page (`page`: its view3d, state, session and controls). */
/** The status line while a position is set up (whatever else the table's state says). */
export const EDITING_WORDS = "Setting up a position: nothing is played until you play from here.";

export class PracticeTool {
  constructor(page) {
    this.page = page;
    this.editing = null; // {balls} while a position is being set up, else null
    this.drag = null; // {id, from} while a ball is dragged
    this.link = null; // the last shared position's link
    this.notice = null; // the last refusal, in the server's words
    this.el = Object.assign(document.createElement("div"), { className: "actions practice", id: "practice" });
    document.getElementById("actions").after(this.el);
    this.bindPointer(page.view3d.canvas);
    hooks.practice = () => ({ editing: this.editing ? { ...this.editing.balls } : null, link: this.link });
  }

  get view() {
    return this.page.state.view;
  }

  get table() {
    return this.page.view3d.table;
  }

  /** A new table version was shown: it ends any editing. */
  shown() {
    this.editing = null;
    this.drag = null;
    this.show();
  }

  show() {
    const v = this.view;
    const busy = v.status !== "playing" || this.page.shooter !== null;
    const items = this.editing ? this.editorItems() : this.toolItems(busy);
    if (this.notice) items.push(Object.assign(document.createElement("p"), { className: "share refusal-text", textContent: this.notice }));
    if (this.link) {
      const p = Object.assign(document.createElement("p"), { className: "share" });
      p.append("Position link: ", Object.assign(document.createElement("a"), { id: "position-link", href: this.link, textContent: this.link }));
      items.push(p);
    }
    this.el.replaceChildren(...items);
  }

  toolItems(busy) {
    const v = this.view;
    const presets = Object.keys(v.presets ?? {});
    const select = Object.assign(document.createElement("select"), { id: "preset", ariaLabel: "Named position" });
    select.append(new Option("The break (re-rack)", ""), ...presets.map((name) => new Option(PRESET_WORDS[name] ?? name, name)));
    const setUp = () => this.rack(select.value ? v.presets[select.value] : null);
    const retake = v.retake || Boolean(v.last_outcome?.input?.strike);
    return [
      button("Set up a position", () => this.edit(), { id: "edit-position", disabled: busy }),
      select,
      button("Set up", setUp, { id: "preset-go", disabled: busy }),
      button("Re-rack", () => this.rack(null), { id: "rerack", disabled: busy }),
      button("Take the shot again", () => this.retake(), { id: "retake", disabled: busy || !retake }),
      button("Share this position", () => this.share(v.state.balls), { id: "share-position" }),
    ];
  }

  editorItems() {
    const hint = Object.assign(document.createElement("p"), {
      className: "share",
      textContent: "Drag a ball to move it, off the table to take it off; click a ball below to put it on.",
    });
    const off = this.view.ball_set.filter((id) => !(id in this.editing.balls));
    const tray = off.map((id) => button(id, () => this.putOn(id), { className: "tray-ball", title: `Put the ${id} on the table` }));
    tray.forEach((b, k) => (b.dataset.ball = off[k]));
    return [
      hint,
      ...tray,
      button("Play from here", () => this.rack(this.editing.balls), { id: "apply-position", className: "primary" }),
      button("Cancel", () => this.cancel(), { id: "cancel-position" }),
      button("Share this position", () => this.share(this.editing.balls), { id: "share-position" }),
    ];
  }

  /** Start setting up a position from the balls as they lie: the cue and aim are put away. */
  edit() {
    this.notice = null;
    this.editing = { balls: structuredClone(this.view.state.balls) };
    const v3 = this.page.view3d;
    this.page.controls.setEnabled(null);
    v3.setTargets(null);
    v3.showRegion(null);
    v3.setAim(null, {});
    v3.setMode("top");
    v3.setBalls(this.editing.balls);
    // The stroke's controls wait until the position is played (the page's next render).
    for (const id of ["controls", "keys", "view-toggle"]) document.getElementById(id).hidden = true;
    document.getElementById("hint").textContent = "";
    document.getElementById("status").textContent = EDITING_WORDS;
    this.show();
  }

  cancel() {
    this.editing = null;
    this.page.shown();
  }

  /** Put ball `id` on a free place near the table's centre. */
  putOn(id) {
    const t = this.table;
    const p = freePlace(t, "anywhere", this.editing.balls, id, [t.w / 2, t.l / 2]);
    if (!p) return;
    this.editing.balls[id] = p;
    this.page.view3d.setBalls(this.editing.balls);
    this.show();
  }

  /** Where a ball dropped at p goes: kept on the bed (null: dragged off the table, taken off). */
  drop(p) {
    const { w, l, R } = this.table;
    if (!p || p[0] < 0 || p[0] > w || p[1] < 0 || p[1] > l) return null;
    return [Math.min(Math.max(p[0], R), w - R), Math.min(Math.max(p[1], R), l - R)];
  }

  bindPointer(canvas) {
    const nearest = (p) => {
      let best = null;
      for (const [id, q] of Object.entries(this.editing.balls)) {
        const d = Math.hypot(q[0] - p[0], q[1] - p[1]);
        if (d < 1.6 * this.table.R && (!best || d < best.d)) best = { id, d };
      }
      return best?.id ?? null;
    };
    canvas.addEventListener(
      "pointerdown",
      (e) => {
        if (!this.editing) return;
        e.stopImmediatePropagation();
        const p = this.page.view3d.pointerToTable(e);
        const id = p && nearest(p);
        if (!id) return;
        canvas.setPointerCapture(e.pointerId);
        this.drag = { id, from: this.editing.balls[id] };
      },
      { capture: true },
    );
    canvas.addEventListener(
      "pointermove",
      (e) => {
        if (!this.editing) return;
        e.stopImmediatePropagation();
        const p = this.drag && this.page.view3d.pointerToTable(e);
        if (!p) return;
        this.editing.balls[this.drag.id] = p;
        this.page.view3d.setBalls(this.editing.balls);
      },
      { capture: true },
    );
    const end = (e) => {
      if (!this.editing) return;
      e.stopImmediatePropagation();
      if (!this.drag) return;
      const { id, from } = this.drag;
      this.drag = null;
      const at = this.drop(this.page.view3d.pointerToTable(e));
      this.notice = null;
      if (!at) delete this.editing.balls[id];
      else if (overlap(this.table, this.editing.balls, id, at)) {
        this.editing.balls[id] = from;
        this.notice = "Balls cannot overlap: the ball went back.";
      } else this.editing.balls[id] = at;
      this.page.view3d.setBalls(this.editing.balls);
      this.show();
    };
    canvas.addEventListener("pointerup", end, { capture: true });
    canvas.addEventListener("pointercancel", end, { capture: true });
  }

  /** The next rack: from `position`, or the game's own rack (null). */
  async rack(position) {
    await this.act("rack", position ? { position } : {});
  }

  async retake() {
    await this.act("retake");
  }

  /** A practice command; its answer (the table re-racked) is shown at once, a refusal in the
   *  server's words. */
  async act(name, body) {
    this.notice = null;
    try {
      const view = await this.page.session.action(name, body);
      if (view.version > this.page.session.version) this.page.session.takeView(view);
    } catch (e) {
      if (!(e instanceof ApiError)) throw e;
      this.notice = `Refused (${e.code}): ${e.message}`;
      this.show();
    }
  }

  /** A link that sets up `balls` (checked by the server first), copied to the clipboard. */
  async share(balls) {
    const v = this.view;
    const body = { game: v.game, size: v.options.size, reds: v.options.reds, position: balls };
    this.notice = null;
    try {
      const shared = await post("/api/positions", body);
      this.link = `${location.origin}${shared.url}`;
      navigator.clipboard?.writeText(this.link).catch(() => {});
    } catch (e) {
      if (!(e instanceof ApiError)) throw e;
      this.notice = `Cannot share (${e.code}): ${e.message}`;
    }
    this.show();
  }
}
