// /practice/{game} and /table/{id}: the table in 3D, the controls of the player to act, and
// the match around it (scores, the referee's words, choices, clock, presence, quick messages,
// resign, rematch). Everything shown comes from the server: the client sends intents only.
import { ApiError, currentPlayer, get, post } from "../net/api.js";
import { ensurePlayer, showWho } from "../net/identity.js";
import { Controls } from "../play/controls.js";
import { TableSession } from "../play/session.js";
import { missingExtra, readExtras, showExtras } from "../play/extras.js";
import { TableSounds } from "../play/sound.js";
import { nextWords, optionWords, outcomeWords, playerName, scoreWords, seatName } from "../play/words.js";
import { Animation } from "../three/animate.js";
import { TableView } from "../three/view.js";

const QUICK_MESSAGES = {
  hello: "Hello",
  good_shot: "Good shot",
  nice_try: "Nice try",
  well_played: "Well played",
  oops: "Oops",
  thanks: "Thanks",
  good_game: "Good game",
  bye: "Bye",
};

/** Seconds left on the shot clock from which it is shown in alarm. */
const URGENT_S = 5;

const $ = (id) => document.getElementById(id);
const geometry = fetch("/web/tables").then((r) => r.json());

/** Diagnostics the browser tests read: per animation, its frame intervals and the main thread's
 *  time per frame (ms), the resolution scale reached and whether the renderer was taken for a
 *  software one; how many table states have been shown, and the version of the last;
 *  balls(): where each ball is drawn, in table coordinates; screenOf(p): where on the page a
 *  table point is drawn; camera(): the view last drawn ("aim" or "top"); drawn(): whether
 *  every change asked for has been drawn; sound(): the sounds' state and counts. */
const diagnostics = { animations: [], shown: 0 };
window.billiards = diagnostics;
const sounds = new TableSounds();
diagnostics.sound = () => sounds.stats();

function button(label, onClick, className = "") {
  const b = document.createElement("button");
  b.type = "button";
  b.textContent = label;
  b.className = className;
  b.addEventListener("click", onClick);
  return b;
}

/** The id of this player's practice table for `game`: the one kept from last time if it still
 *  runs, else a new one. */
async function practiceTable(game, me) {
  const key = `billiards.practice.${game}`;
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

class PlayPage {
  constructor(tableId, me) {
    this.me = me;
    this.view3d = null;
    this.shown = null; // the table as shown (a TableView, advanced by each outcome shown)
    this.placement = null;
    this.lastWords = "";
    this.session = new TableSession(tableId, {
      onView: (v) => this.showView(v),
      onOutcome: (m) => this.showOutcome(m),
      onChat: (m) => this.banner(`${m.from_name}: ${QUICK_MESSAGES[m.message] ?? m.message}`, 4000),
      onPresence: (m) => this.showPresence(m.presence, m.grace_until),
      onConnection: (s) => {
        if (s === "closed") this.banner("Connection lost: reconnecting...");
        else this.banner(null);
      },
    });
    setInterval(() => this.tickClock(), 500);
  }

  mySeat(view = this.shown) {
    if (!this.me || !view) return null;
    const seat = view.seats.findIndex((s) => s?.id === this.me.id);
    return seat < 0 ? null : seat;
  }

  async setup(view) {
    const table = (await geometry)[view.game];
    document.title = `billiards: ${view.game}`;
    this.view3d = new TableView($("table"), table, view.game);
    diagnostics.balls = () => this.view3d.drawnBalls();
    diagnostics.screenOf = (p) => this.view3d.screenOf(p);
    diagnostics.camera = () => this.view3d.shownMode;
    diagnostics.drawn = () => !this.view3d.pending && !this.view3d.animating;
    this.controls = new Controls(
      this.view3d,
      {
        canvas: $("table"),
        power: $("power"),
        powerOut: $("power-out"),
        elevation: $("elevation"),
        elevationOut: $("elevation-out"),
        tip: $("tip"),
        hit: $("hit"),
        viewToggle: $("view-toggle"),
      },
      { strike: (aim) => this.strike(aim), place: (p) => this.place(p) },
    );
    this.chatButtons();
    sounds.bindToggle($("sound"));
  }

  async showView(view) {
    if (!this.view3d) await this.setup(view);
    this.animation?.stop();
    this.shown = structuredClone(view);
    this.view3d.setBalls(view.state.balls);
    this.placement = null;
    this.showPresence(view.presence, this.grace);
    this.session.beat(this.mySeat() !== null && view.status === "playing");
    if (view.last_outcome?.decision && !this.lastWords) this.lastWords = outcomeWords(view, view.last_outcome);
    this.refresh();
    diagnostics.shown += 1;
    diagnostics.version = view.version;
  }

  showOutcome(message) {
    const shown = this.shown;
    const after = () => {
      Object.assign(shown, {
        state: message.state,
        next: message.next,
        rack: message.rack,
        racks_won: message.racks_won,
        status: message.status,
        winner: message.winner,
        version: message.version,
      });
      this.view3d.setBalls(message.state.balls);
      this.placement = null;
      if (message.decision) {
        this.lastWords = outcomeWords(shown, message);
      } else if (message.void) {
        this.lastWords = `The shot could not be played (${message.void}).`;
      }
      this.refresh();
      diagnostics.shown += 1;
      diagnostics.version = message.version;
    };
    if (!message.trajectory) {
      after();
      return Promise.resolve();
    }
    this.controls.setEnabled(null);
    this.status(`${seatName(shown, message.seat)} shoots...`);
    return new Promise((resolve) => {
      const animation = new Animation(this.view3d, message.trajectory, {
        onEvent: (type, speed) => sounds.play(type, speed),
        onDone: () => {
          diagnostics.animations.push({
            balls: Object.keys(message.trajectory.balls).length,
            duration: message.trajectory.duration,
            intervals: animation.frameTimes,
            draws: this.view3d.drawTimes,
            scale: this.view3d.scale,
            software: this.view3d.software,
          });
          after();
          resolve();
        },
      });
      this.animation = animation;
      animation.play();
    });
  }

  status(text) {
    $("status").textContent = text;
  }

  refresh() {
    const v = this.shown;
    const mine = this.mySeat();
    const toAct = v.status === "playing" && v.next && v.next.seat === mine;
    this.status([this.lastWords, nextWords(v), scoreWords(v)].filter(Boolean).join(" "));
    this.scoreboard(v);
    const shooting = toAct && v.next.kinds.includes("shot");
    showExtras($("extras"), shooting ? v : null);
    // A called pocket is ringed on the table as soon as it is chosen.
    this.view3d.markPocket(null);
    $("extras").querySelector('select[name="call"]')?.addEventListener("change", (e) => this.view3d.markPocket(e.target.value || null));
    if (shooting) {
      this.ensureCueBall(v);
      this.aimAtNearest(v.next.cue_ball);
    }
    this.controls.setEnabled(shooting ? v.next.cue_ball : null, { placing: shooting ? v.next.ball_in_hand : null });
    this.choices(toAct && v.next.kinds.includes("choice") ? v.next.options : []);
    // Spectators watch: no cue, no stroke controls; nor before the match starts or once over.
    const choosing = toAct && v.next.kinds.includes("choice");
    for (const id of ["controls", "keys"]) $(id).hidden = mine === null || v.status !== "playing" || choosing;
    // The aim view looks along the cue: without one to aim (a spectator, the opponent's turn, a
    // match over) the table is seen from above, with no view to switch to.
    $("view-toggle").hidden = !shooting;
    this.actions(v, mine);
  }

  scoreboard(v) {
    const box = $("players");
    box.replaceChildren();
    for (const seat of [0, 1]) {
      const name = document.createElement("span");
      const acting = v.status === "playing" && (v.mode === "practice" ? v.state.turn : v.next?.seat) === seat;
      name.className = `name${acting ? " to-act" : ""}`;
      name.textContent = playerName(v, seat) + (v.presence?.[seat] === false && v.seats[seat] ? " (disconnected)" : "");
      const score = document.createElement("span");
      score.className = "score";
      score.textContent = String(v.state.scores[seat]);
      box.append(name, score);
    }
    const clock = document.createElement("span");
    clock.className = "clock";
    clock.id = "clock";
    box.append(clock);
    this.showClock();
  }

  tickClock() {
    if (this.goneSeat() >= 0) {
      this.presenceBanner();
      const claim = this.claimable();
      if (claim !== this.claimShown) this.actions(this.shown, this.mySeat());
      this.claimShown = claim;
    }
    this.showClock();
  }

  /** The seconds left to the player to act (the server rules the deadline; this only shows it). */
  showClock() {
    const clock = $("clock");
    const deadline = this.shown?.next?.deadline;
    if (!clock) return;
    const left = deadline ? Math.max(0, Math.ceil(deadline - Date.now() / 1000)) : null;
    clock.textContent = left === null ? "" : `Shot clock ${left} s`;
    clock.classList.toggle("urgent", left !== null && left <= URGENT_S);
  }

  /** With the cue ball in hand and off the table, put it on the region's usual spot, or the
   *  nearest place round it clear of the other balls (the server still judges the place). */
  ensureCueBall(v) {
    const cue = v.next.cue_ball;
    if (v.state.balls[cue] || !v.next.ball_in_hand) return;
    const t = this.view3d.table;
    const [x0, y0] = v.next.ball_in_hand === "D" ? [t.w / 2, t.baulk_y - t.d_radius / 2] : (t.spots.head ?? [t.w / 2, t.l / 4]);
    const others = Object.values(v.state.balls);
    const clear = ([x, y]) => others.every((p) => Math.hypot(p[0] - x, p[1] - y) > 2.2 * t.R);
    for (let ring = 0; ring < 12; ring++) {
      for (let k = 0; k < Math.max(1, ring * 6); k++) {
        const a = (2 * Math.PI * k) / Math.max(1, ring * 6);
        const p = [x0 + ring * 2.5 * t.R * Math.cos(a), y0 + ring * 2.5 * t.R * Math.sin(a)];
        if (clear(p)) return this.place(p);
      }
    }
    this.place([x0, y0]);
  }

  place(p) {
    const v = this.shown;
    const t = this.view3d.table;
    const x = Math.min(t.w - t.R, Math.max(t.R, p[0]));
    const y = Math.min(t.l - t.R, Math.max(t.R, p[1]));
    this.placement = [x, y];
    this.view3d.setBalls({ ...v.state.balls, [v.next.cue_ball]: this.placement });
    this.controls.show();
  }

  /** Aim at the nearest ball the shooter may want: in snooker a red when reds are on (so the
   *  break aims up the table at the pack), else the nearest ball. */
  aimAtNearest(cue) {
    const from = this.view3d.ballAt(cue);
    if (!from) return;
    const { state } = this.shown;
    const reds = state.on === "red" && this.shown.game === "snooker";
    let best = null;
    for (const [id, p] of Object.entries(state.balls)) {
      if (id === cue || (reds && !id.startsWith("red"))) continue;
      const d = Math.hypot(p[0] - from[0], p[1] - from[1]);
      if (!best || d < best.d) best = { d, p };
    }
    if (best) this.controls.set({ heading: (Math.atan2(best.p[1] - from[1], best.p[0] - from[0]) * 180) / Math.PI });
  }

  async strike(aim) {
    const v = this.shown;
    const missing = missingExtra($("extras"));
    if (missing) {
      // Not sent: the referee would refuse it. The controls stay as they were, aim and all.
      this.controls.setEnabled(v.next.cue_ball, { placing: v.next.ball_in_hand });
      this.status(missing.words);
      missing.input.focus();
      return;
    }
    const round = (x, digits) => Number(x.toFixed(digits));
    const input = {
      strike: {
        ball: v.next.cue_ball,
        speed: round(aim.speed, 3),
        heading: round(aim.heading, 3),
        elevation: aim.elevation,
        a: round(aim.a, 3),
        b: round(aim.b, 3),
      },
    };
    if (this.placement) input.place = this.placement;
    Object.assign(input, readExtras($("extras")));
    await this.send(input, "Shot sent.");
  }

  async send(input, words) {
    try {
      await this.session.intent(input);
      this.status(words);
    } catch (e) {
      this.status(`Refused: ${e.message}`);
      if (e.code === "stale_version") await this.session.resync();
      else this.refresh();
    }
  }

  choices(options) {
    $("choices").replaceChildren(...options.map((o) => button(optionWords(o), () => this.send({ option: o }, "Choice sent."))));
  }

  actions(v, mine) {
    const box = $("actions");
    const list = [];
    const act = (label, name) =>
      button(label, async () => {
        try {
          await this.session.action(name);
        } catch (e) {
          this.status(`Refused: ${e.message}`);
        }
      });
    if (mine === null && v.status === "open") {
      list.push(
        button(
          "Join this table",
          async () => {
            this.me = await ensurePlayer();
            try {
              await this.session.action("join");
            } catch (e) {
              this.status(`Refused: ${e.message}`);
            }
          },
          "primary",
        ),
      );
    }
    if (mine !== null && v.mode !== "practice") {
      if (v.status === "playing") list.push(act("Resign", "resign"));
      if (this.claimable() && this.goneSeat() === 1 - mine) list.push(act("Claim the win", "claim"));
      if (v.status === "over") list.push(act(v.rematch?.[1 - mine] ? "Accept the rematch" : "Offer a rematch", "rematch"));
      if (v.status === "open") list.push(act("Cancel", "leave"));
    }
    if (v.rematch_table) {
      const a = document.createElement("a");
      a.href = `/table/${v.rematch_table}`;
      a.className = "button";
      a.textContent = "Go to the rematch";
      list.push(a);
    }
    if (mine === null && v.mode !== "practice" && v.status === "playing") {
      list.push(Object.assign(document.createElement("p"), { className: "share muted", textContent: "You are watching this match." }));
    }
    if (v.options.private && v.status === "open" && mine !== null) {
      // The link is the invitation: the table is in no lobby list.
      const share = document.createElement("p");
      share.className = "share";
      share.id = "invite";
      const link = Object.assign(document.createElement("a"), { href: `/table/${v.id}`, textContent: `${location.origin}/table/${v.id}` });
      share.append("Private table: send this link to your opponent ", link);
      list.push(share);
    }
    if (v.mode !== "practice") {
      list.push(
        button("Copy link", () => {
          navigator.clipboard?.writeText(`${location.origin}/table/${v.id}`);
          this.banner("Link copied", 1500);
        }),
      );
    }
    box.replaceChildren(...list);
    $("chat").hidden = v.mode === "practice";
  }

  chatButtons() {
    $("chat").replaceChildren(
      ...Object.entries(QUICK_MESSAGES).map(([code, words]) =>
        button(words, async () => {
          this.me ??= await ensurePlayer();
          this.session.action("messages", { message: code }).catch((e) => this.banner(e.message, 2000));
        }),
      ),
    );
  }

  showPresence(presence, graceUntil) {
    if (!this.shown) return;
    this.shown.presence = presence;
    this.grace = graceUntil ?? [null, null];
    this.presenceBanner();
    if (this.shown.state) {
      this.scoreboard(this.shown);
      this.actions(this.shown, this.mySeat());
    }
  }

  /** The seat whose player is gone from a running match, or -1. */
  goneSeat() {
    const v = this.shown;
    if (!v || v.status !== "playing") return -1;
    return v.presence.findIndex((p, seat) => !p && v.seats[seat]);
  }

  /** May the opponent of the gone seat claim the win yet (its grace period is over)? */
  claimable() {
    const gone = this.goneSeat();
    const until = gone >= 0 ? this.grace?.[gone] : null;
    return until != null && until <= Date.now() / 1000;
  }

  presenceBanner() {
    const gone = this.goneSeat();
    if (gone < 0) return this.banner(null);
    const until = this.grace?.[gone];
    const left = until ? Math.max(0, Math.ceil(until - Date.now() / 1000)) : null;
    const wait = left ? ` (the win may be claimed in ${left} s)` : left === 0 ? " (the win may be claimed)" : "";
    this.banner(`${seatName(this.shown, gone)} disconnected${wait}`);
  }

  banner(text, ms) {
    const el = $("banner");
    clearTimeout(this.bannerTimer);
    el.hidden = !text;
    el.textContent = text ?? "";
    if (text && ms) this.bannerTimer = setTimeout(() => (el.hidden = true), ms);
  }
}

async function main() {
  const [, kind, param] = location.pathname.split("/");
  let me;
  let tableId = param;
  if (kind === "practice") {
    me = await ensurePlayer();
    tableId = await practiceTable(param, me);
  } else {
    me = await currentPlayer();
    showWho(me);
  }
  const page = new PlayPage(tableId, me);
  await page.session.start();
}

main().catch((e) => {
  document.getElementById("status").textContent = `Could not open the table: ${e.message}`;
});
