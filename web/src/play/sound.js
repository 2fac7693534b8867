// The table's sounds, synthesised with the Web Audio API from a shot's events as the animation
// reaches them: a click for ball on ball, a thud for a cushion (or a jaw), a drop for a pocket,
// a tap for the cue's strike. No sound files, so the first load stays small. Browsers let a page
// start audio only after a user gesture, so the audio context is made on the first key press or
// pointer press; before that, and while muted, nothing is scheduled. The mute choice is kept in
// localStorage.

const MUTED_KEY = "billiards.muted";
/** Speeds (m/s) that give a full-strength sound: a hard break's clicks and thuds. */
const FULL_SPEED = { strike: 8, ball_ball: 5, ball_cushion: 3, ball_jaw: 3, ball_pocket: 2.5 };
/** The events that make a sound; the others (motion state changes) are silent. */
export const SOUNDING = Object.keys(FULL_SPEED);
/** At most this many sounds start within one window of WINDOW_S seconds (a break's first
 *  instants hold dozens of contacts: the quietest are dropped, unheard in the crowd anyway). */
const VOICES = 6;
const WINDOW_S = 0.03;
/** Below this strength a sound is not worth its nodes. */
const QUIETEST = 0.02;

export class TableSounds {
  constructor() {
    this.muted = localStorage.getItem(MUTED_KEY) === "1";
    this.context = null;
    this.started = []; // start times of the sounds in the current window
    /** What the browser tests read: sounds scheduled per event type, dropped, muted. */
    this.counts = { scheduled: {}, dropped: 0, muted: 0 };
    this.unlock = () => this.start();
    for (const type of ["keydown", "pointerdown"]) window.addEventListener(type, this.unlock, true);
  }

  /** Make (or resume) the audio context: called on a user gesture. */
  start() {
    for (const type of ["keydown", "pointerdown"]) window.removeEventListener(type, this.unlock, true);
    if (this.context) return;
    const Context = window.AudioContext ?? window.webkitAudioContext;
    if (!Context) return;
    const context = new Context();
    this.context = context;
    this.out = context.createGain();
    this.out.gain.value = 0.5;
    this.out.connect(context.destination);
    // One second of white noise, the raw stuff of clicks and rattles.
    this.noise = context.createBuffer(1, context.sampleRate, context.sampleRate);
    const data = this.noise.getChannelData(0);
    for (let i = 0; i < data.length; i++) data[i] = Math.random() * 2 - 1;
  }

  /** The state the browser tests read: the context's ("none" before a gesture), and counts. */
  stats() {
    return { state: this.context?.state ?? "none", muted: this.muted, ...structuredClone(this.counts) };
  }

  setMuted(muted) {
    this.muted = muted;
    localStorage.setItem(MUTED_KEY, muted ? "1" : "0");
  }

  /** Make `button` the mute toggle (its text and aria-pressed follow the state). */
  bindToggle(button) {
    const show = () => {
      button.textContent = this.muted ? "Sound off" : "Sound on";
      button.setAttribute("aria-pressed", String(!this.muted));
      button.title = this.muted ? "Turn the table's sounds on" : "Mute the table's sounds";
    };
    button.addEventListener("click", () => {
      this.setMuted(!this.muted);
      show();
    });
    show();
  }

  /** The sound of one event of type `type` (see SOUNDING) at `speed` m/s, now. */
  play(type, speed) {
    const full = FULL_SPEED[type];
    if (!full) return;
    if (this.muted) {
      this.counts.muted += 1;
      return;
    }
    const context = this.context;
    if (!context) return;
    if (context.state === "suspended") context.resume().catch(() => {});
    const strength = Math.min(1, speed / full);
    const now = context.currentTime;
    this.started = this.started.filter((t) => now - t < WINDOW_S);
    if (strength < QUIETEST || this.started.length >= VOICES) {
      this.counts.dropped += 1;
      return;
    }
    this.started.push(now);
    this.counts.scheduled[type] = (this.counts.scheduled[type] ?? 0) + 1;
    VOICE[type](this, now, strength);
  }

  /** A sine sweeping from f0 to f1 Hz, decaying exponentially over `decay` s. */
  tone(at, f0, f1, decay, gain) {
    const c = this.context;
    const osc = c.createOscillator();
    osc.frequency.setValueAtTime(f0, at);
    osc.frequency.exponentialRampToValueAtTime(f1, at + decay);
    osc.connect(this.envelope(at, decay, gain));
    osc.start(at);
    osc.stop(at + decay * 1.2);
  }

  /** A burst of noise through a band-pass (or low-pass) filter at `freq` Hz. */
  burst(at, filter, freq, q, decay, gain) {
    const c = this.context;
    const src = c.createBufferSource();
    src.buffer = this.noise;
    const f = c.createBiquadFilter();
    f.type = filter;
    f.frequency.value = freq;
    f.Q.value = q;
    src.connect(f).connect(this.envelope(at, decay, gain));
    src.start(at, Math.random() * 0.5);
    src.stop(at + decay * 1.2);
  }

  envelope(at, decay, gain) {
    const g = this.context.createGain();
    g.gain.setValueAtTime(0.0001, at);
    g.gain.exponentialRampToValueAtTime(gain, at + 0.002);
    g.gain.exponentialRampToValueAtTime(0.0001, at + decay);
    g.connect(this.out);
    return g;
  }
}

/** Each event type's sound: (sounds, start time, strength in [0, 1]). */
const VOICE = {
  // Phenolic on phenolic: a bright, very short click, higher and louder the harder.
  ball_ball: (s, at, k) => {
    s.burst(at, "bandpass", 3200 + 1800 * k, 3, 0.025, 0.9 * k);
    s.tone(at, 2600 + 900 * k, 2200, 0.03, 0.35 * k);
  },
  // Rubber and rail: a dull, low thud.
  ball_cushion: (s, at, k) => {
    s.tone(at, 150, 70, 0.12, 0.8 * k);
    s.burst(at, "lowpass", 500, 0.7, 0.05, 0.4 * k);
  },
  ball_jaw: (s, at, k) => {
    s.tone(at, 210, 110, 0.08, 0.6 * k);
    s.burst(at, "lowpass", 900, 0.7, 0.04, 0.35 * k);
  },
  // Into the pocket: a soft thump, then the ball rattling down.
  ball_pocket: (s, at, k) => {
    const g = 0.4 + 0.6 * k;
    s.tone(at, 95, 55, 0.18, 0.7 * g);
    for (const [dt, f] of [[0.05, 1400], [0.11, 1100], [0.16, 900]]) s.burst(at + dt, "bandpass", f, 4, 0.03, 0.35 * g);
  },
  // Leather tip on the cue ball: a short knock.
  strike: (s, at, k) => {
    s.burst(at, "bandpass", 1600 + 600 * k, 1.5, 0.02, 0.8 * (0.3 + 0.7 * k));
    s.tone(at, 900, 600, 0.04, 0.3 * (0.3 + 0.7 * k));
  },
};
