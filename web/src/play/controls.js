// Aiming and striking: mouse or touch drag on the table, the keyboard, and the on-screen power
// slider, tip-offset widget, elevation slider and Hit button; with the cue ball in hand, dragging
// it or Alt + the arrow keys moves it. It edits one aim
// {heading, elevation, a, b, power} and calls `strike(aim)`; it knows nothing of the server.
import { FINE_PLACE_STEP, PLACE_STEP } from "./placing.js";

/** Tip offsets farther from centre than this (fraction of R) would miscue (rules.inputs). */
export const MISCUE_LIMIT = 0.5;
/** Cue speed at power 0 and 1 (m/s); the rules accept (0, 12]. */
export const MIN_SPEED = 0.3;
export const MAX_SPEED = 10;
/** Heading steps (degrees) of the arrow keys, without and with Ctrl; spin step (of R). */
const STEP = 0.5;
const FINE_STEP = 0.05;
const SPIN_STEP = 0.05;
/** Holding Space fills the power bar in this many seconds. */
const FILL_TIME = 1.6;
/** Heading change per pixel of horizontal drag in the aim view (degrees). */
const DRAG_RATE = 0.15;

/** The power after holding Space for `ms` milliseconds. */
function chargeAfter(ms) {
  return Math.min(1, Math.max(0, ms / 1000 / FILL_TIME));
}

export function speedOf(power) {
  return MIN_SPEED + (MAX_SPEED - MIN_SPEED) * power;
}

/** (a, b) pulled back inside the miscue limit. */
export function clampTip(a, b) {
  const r = Math.hypot(a, b);
  return r <= MISCUE_LIMIT ? [a, b] : [(a / r) * MISCUE_LIMIT, (b / r) * MISCUE_LIMIT];
}

const wrap = (deg) => ((deg % 360) + 360) % 360;

/** Whether element t takes typed keys of its own (a text field, a list, a check box). */
const typing = (t) => t instanceof HTMLSelectElement || t instanceof HTMLTextAreaElement || (t instanceof HTMLInputElement && t.type !== "range");

export class Controls {
  /**
   * view: the TableScene; els: {canvas, power, powerOut, elevation, elevationOut, tip, hit,
   * viewToggle}; strike(aim) plays the shot; place(point) moves the cue ball in hand; aimed()
   * is told of every change of the aim.
   */
  constructor(view, els, { strike, place, aimed }) {
    this.view = view;
    this.els = els;
    this.strikeShot = strike;
    this.place = place;
    this.aimed = aimed;
    this.aim = { heading: 90, elevation: 0, a: 0, b: 0, power: Number(els.power.value) };
    this.enabled = false;
    this.placing = null; // the ball-in-hand region while the cue ball may be moved
    this.charging = null;
    this.bindKeys();
    this.bindPointer();
    this.bindWidgets();
    this.show();
  }

  /** Allow shooting cue ball `cue` (placing it first in region `placing`, if given), or forbid
   *  it (cue null: not our turn, balls moving, a choice pending). */
  setEnabled(cue, { placing = null } = {}) {
    const enabled = Boolean(cue);
    this.cue = cue;
    this.enabled = enabled;
    this.placing = enabled ? placing : null;
    this.els.hit.disabled = !enabled;
    this.charging = null;
    this.show();
  }

  set(changes) {
    Object.assign(this.aim, changes);
    this.aim.heading = wrap(this.aim.heading);
    [this.aim.a, this.aim.b] = clampTip(this.aim.a, this.aim.b);
    this.aim.power = Math.min(1, Math.max(0, this.aim.power));
    this.show();
  }

  show() {
    const { aim, els } = this;
    els.power.value = aim.power;
    els.powerOut.textContent = `${speedOf(aim.power).toFixed(1)} m/s`;
    els.elevation.value = aim.elevation;
    els.elevationOut.textContent = `${aim.elevation}\u00b0`;
    const dot = els.tip.querySelector(".dot");
    // The widget's disc is the ball's face: the limit circle (half the radius) is the miscue line.
    dot.style.left = `${50 + aim.a * 50}%`;
    dot.style.top = `${50 - aim.b * 50}%`;
    const words = aim.a === 0 && aim.b === 0 ? "centre" : `side ${aim.a.toFixed(2)}, ${aim.b >= 0 ? "top" : "back"} ${Math.abs(aim.b).toFixed(2)}`;
    els.tip.setAttribute("aria-valuetext", words);
    this.view.setAim(this.enabled ? this.cue : null, aim);
    this.aimed?.();
  }

  strike() {
    if (!this.enabled || this.aim.power <= 0) return;
    this.enabled = false;
    this.els.hit.disabled = true;
    this.strikeShot({ ...this.aim, speed: speedOf(this.aim.power) });
  }

  bindKeys() {
    window.addEventListener("keydown", (e) => {
      if (e.key === "v" || e.key === "V") {
        if (!typing(e.target)) this.toggleView();
        return;
      }
      if (!this.enabled || !this.answersGameKey(e)) return;
      if (this.gameKey(e)) e.preventDefault();
    });
    window.addEventListener("keyup", (e) => {
      if (e.key !== " " || !this.charging) return;
      e.preventDefault();
      // The power is the time held, whether or not the frames kept up with it.
      this.set({ power: chargeAfter(performance.now() - this.charging) });
      this.charging = null;
      this.strike();
    });
  }

  /** Whether key event e is the game's: everywhere but in a control that owns it. The power
   *  and elevation sliders keep Up/Down (their own value), the spin disc takes the arrows
   *  as spin (its label says so), form fields and buttons keep their keys. */
  answersGameKey(e) {
    const t = e.target;
    if (t === this.els.tip) return e.key === " " || e.key.startsWith("Arrow");
    if (t instanceof HTMLInputElement && t.type === "range") return e.key === " " || e.key === "ArrowLeft" || e.key === "ArrowRight";
    return !typing(t) && !(t instanceof HTMLButtonElement);
  }

  /** Act on game key e; whether it was one. */
  gameKey(e) {
    const { aim } = this;
    const onTip = e.target === this.els.tip;
    if (e.altKey && this.placing && e.key.startsWith("Arrow")) return this.nudgeCueBall(e);
    const step = e.ctrlKey || e.metaKey ? FINE_STEP : STEP;
    const spin = e.shiftKey || onTip;
    if (e.key === "ArrowLeft" && spin) this.set({ a: aim.a - SPIN_STEP });
    else if (e.key === "ArrowRight" && spin) this.set({ a: aim.a + SPIN_STEP });
    else if (e.key === "ArrowLeft") this.set({ heading: aim.heading + step });
    else if (e.key === "ArrowRight") this.set({ heading: aim.heading - step });
    else if (e.key === "ArrowUp") this.set({ b: aim.b + SPIN_STEP });
    else if (e.key === "ArrowDown") this.set({ b: aim.b - SPIN_STEP });
    else if (e.key === " ") {
      if (!this.charging) this.startCharge();
    } else return false;
    return true;
  }

  /** Alt + an arrow key moves the cue ball in hand, across the screen as the camera sees it. */
  nudgeCueBall(e) {
    const cue = this.view.ballAt(this.cue);
    if (!cue) return true;
    const step = e.ctrlKey || e.metaKey ? FINE_PLACE_STEP : PLACE_STEP;
    const h = this.view.shownMode === "top" ? 90 : this.aim.heading;
    const forward = [Math.cos((h * Math.PI) / 180), Math.sin((h * Math.PI) / 180)];
    const right = [forward[1], -forward[0]];
    const [dx, dy] = { ArrowUp: forward, ArrowDown: forward.map((v) => -v), ArrowRight: right, ArrowLeft: right.map((v) => -v) }[e.key];
    this.place([cue[0] + dx * step, cue[1] + dy * step]);
    return true;
  }

  startCharge() {
    const started = performance.now();
    this.charging = started;
    this.set({ power: 0 });
    const tick = (now) => {
      if (this.charging !== started) return;
      this.set({ power: chargeAfter(now - started) });
      requestAnimationFrame(tick);
    };
    requestAnimationFrame(tick);
  }

  bindPointer() {
    const canvas = this.els.canvas;
    let drag = null;
    canvas.addEventListener("pointerdown", (e) => {
      if (!this.enabled) return;
      canvas.setPointerCapture(e.pointerId);
      canvas.focus();
      const p = this.view.pointerToTable(e);
      const cue = this.view.ballAt(this.cue);
      const onCue = this.placing && p && (!cue || Math.hypot(p[0] - cue[0], p[1] - cue[1]) < 3 * this.view.table.R);
      drag = { x: e.clientX, mode: onCue ? "place" : "aim", heading: this.aim.heading };
      if (drag.mode === "aim" && this.view.shownMode === "top") this.aimAt(p);
    });
    canvas.addEventListener("pointermove", (e) => {
      if (!drag || !this.enabled) return;
      if (drag.mode === "place") {
        const p = this.view.pointerToTable(e);
        if (p) this.place(p);
      } else if (this.view.shownMode === "top") {
        this.aimAt(this.view.pointerToTable(e));
      } else {
        this.set({ heading: drag.heading - (e.clientX - drag.x) * DRAG_RATE });
      }
    });
    const end = () => {
      drag = null;
    };
    canvas.addEventListener("pointerup", end);
    canvas.addEventListener("pointercancel", end);
    canvas.addEventListener(
      "wheel",
      (e) => {
        e.preventDefault();
        this.view.aimDistance = Math.min(2.5, Math.max(0.35, this.view.aimDistance * (e.deltaY > 0 ? 1.1 : 1 / 1.1)));
        this.view.invalidate();
      },
      { passive: false },
    );
  }

  /** Aim the cue ball at table point p (top view). */
  aimAt(p) {
    const cue = this.view.ballAt(this.cue);
    if (!p || !cue || Math.hypot(p[0] - cue[0], p[1] - cue[1]) < 1e-3) return;
    this.set({ heading: (Math.atan2(p[1] - cue[1], p[0] - cue[0]) * 180) / Math.PI });
  }

  toggleView() {
    const top = this.view.mode === "aim";
    this.view.setMode(top ? "top" : "aim");
    this.els.viewToggle.textContent = top ? "Aim view" : "Top view";
  }

  bindWidgets() {
    const { els } = this;
    els.power.addEventListener("input", () => this.set({ power: Number(els.power.value) }));
    els.elevation.addEventListener("input", () => this.set({ elevation: Number(els.elevation.value) }));
    els.hit.addEventListener("click", () => this.strike());
    els.viewToggle.addEventListener("click", () => this.toggleView());
    const tipAt = (e) => {
      const rect = els.tip.getBoundingClientRect();
      const a = ((e.clientX - rect.left) / rect.width - 0.5) * 2;
      const b = -((e.clientY - rect.top) / rect.height - 0.5) * 2;
      this.set({ a: Math.round(a * 100) / 100, b: Math.round(b * 100) / 100 });
    };
    let down = false;
    els.tip.addEventListener("pointerdown", (e) => {
      down = true;
      els.tip.setPointerCapture(e.pointerId);
      tipAt(e);
    });
    els.tip.addEventListener("pointermove", (e) => down && tipAt(e));
    els.tip.addEventListener("pointerup", () => {
      down = false;
    });
  }
}
