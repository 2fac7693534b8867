// /practice/{game} and /table/{id}: the table in 3D, the controls of the player to act, and
// the match around it. The server's messages change one TableState (play/state.js); every
// change is drawn from it by `render`. What the page keeps of its own is the player's work in
// progress (the cue ball placed in hand, the aim) and the last refusal, shown until the next
// action. Every rule question (what to declare, where to place, what to hit first) is read
// from the server's `next`.
import { currentPlayer, shotId } from "../net/api.js";
import { BOT_PREFIX } from "../net/protocol.js";
import { ensurePlayer, showWho } from "../net/identity.js";
import { aimAtTarget, showBotAim } from "../play/aiming.js";
import { AimShare } from "../play/aimshare.js";
import { Controls } from "../play/controls.js";
import { missingDeclaration, readDeclarations, showDeclarations } from "../play/declarations.js";
import { countShown, hooks } from "../play/hooks.js";
import { MatchActions, resultWords } from "../play/match.js";
import { freePlace, inRegion, keepInRegion, overlap, usualSpot } from "../play/placing.js";
import { showClock, showScoreboard } from "../play/scoreboard.js";
import { EDITING_WORDS, PracticeTool, practiceTable } from "../play/setup.js";
import { tableFor } from "../play/tables.js";
import { TableSession } from "../play/session.js";
import { TableSounds } from "../play/sound.js";
import { TableState } from "../play/state.js";
import { ballWords, nextWords, optionWords, outcomeWords, REGION_WORDS, scoreWords, seatName } from "../play/words.js";
import { Animation } from "../three/animate.js";
import { TableScene } from "../three/view.js";

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

const $ = (id) => document.getElementById(id);
const geometry = fetch("/web/tables").then((r) => r.json());
const sounds = new TableSounds();
hooks.sound = () => sounds.stats();

function button(label, onClick, className = "") {
  const b = Object.assign(document.createElement("button"), { type: "button", textContent: label, className });
  b.addEventListener("click", onClick);
  return b;
}

class PlayPage {
  constructor(tableId, me) {
    this.me = me;
    this.state = new TableState();
    this.view3d = null;
    this.placement = null; // where the player put the cue ball in hand, not yet sent
    this.notice = null; // the last refusal in words, shown until the next action
    this.shooter = null; // the seat whose shot is being animated
    this.match = new MatchActions(this);
    this.aimShare = new AimShare((body) => this.session.action("aim", body));
    this.session = new TableSession(tableId, {
      onView: (v) => this.take(v),
      onOutcome: (m) => this.play(m),
      onChat: (m) => this.banner(`${m.from_name}: ${QUICK_MESSAGES[m.message] ?? m.message}`, 4000),
      onPresence: (m) => {
        this.state.apply(m);
        this.presenceBanner();
        this.render();
      },
      onConnection: (s) => this.banner(s === "closed" ? "Connection lost: reconnecting..." : null),
      onAim: (m) => this.showTheirAim(m),
    });
    setInterval(() => this.tick(), 500);
  }

  get mine() {
    return this.state.seatOf(this.me);
  }

  async setup(view) {
    const table = tableFor(await geometry, view.game, view.options.size);
    document.title = `billiards: ${view.game}`;
    this.view3d = new TableScene($("table"), table, view.game);
    Object.assign(hooks, {
      balls: () => this.view3d.drawnBalls(),
      screenOf: (p) => this.view3d.screenOf(p),
      camera: () => this.view3d.shownMode,
      drawn: () => !this.view3d.pending && !this.view3d.animating,
      aim: () => ({ ...this.controls.aim, contact: this.view3d.contact }),
      placement: () => this.placement,
      botAims: () => this.view3d.botAims ?? 0,
      region: () => this.view3d.regionName,
      theirAim: () => this.theirAim ?? null,
      table: () => this.view3d.table,
    });
    const els = { canvas: $("table"), power: $("power"), powerOut: $("power-out"), elevation: $("elevation") };
    Object.assign(els, { elevationOut: $("elevation-out"), tip: $("tip"), hit: $("hit"), viewToggle: $("view-toggle") });
    this.controls = new Controls(this.view3d, els, {
      strike: (aim) => this.strike(aim),
      place: (p) => this.place(p),
      aimed: () => {
        this.showContact();
        this.shareAim();
      },
    });
    this.chatButtons();
    if (view.mode === "practice") this.practice = new PracticeTool(this);
    hooks.render = () => this.render();
    sounds.bindToggle($("sound"));
    if (view.mode === "match" && view.status !== "over") this.match.noteRating(view.game);
  }

  /** A whole TableView: the start, a resync, a `table` message. */
  async take(view) {
    if (!this.view3d) await this.setup(view);
    this.animation?.stop();
    this.state.apply(view);
    this.shown();
  }

  /** An outcome: its shot animated (the bot's lined up first), then applied. */
  async play(message) {
    this.aimShare.cancel();
    this.theirAim = null;
    if (message.trajectory) {
      this.shooter = message.seat;
      this.notice = null;
      this.controls.setEnabled(null);
      this.render();
      if (message.shot_id.startsWith(BOT_PREFIX)) await showBotAim(this.view3d, this.state.view, message.input);
      await this.animate(message);
      this.shooter = null;
    }
    this.state.apply(message);
    this.shown();
  }

  animate(message) {
    return new Promise((resolve) => {
      const animation = new Animation(this.view3d, message.trajectory, {
        onEvent: (type, speed) => sounds.play(type, speed),
        onDone: () => {
          const { balls, duration } = message.trajectory;
          const v = this.view3d;
          // From the player's release of the stroke (key or click) to its first frame of motion.
          const latency = message.shot_id === this.sentShot ? animation.firstFrameAt - this.releasedAt : null;
          hooks.animations.push({ balls: Object.keys(balls).length, duration, latency, intervals: animation.frameTimes, draws: v.drawTimes, scale: v.scale, software: v.software });
          resolve();
        },
      });
      this.animation = animation;
      animation.play();
    });
  }

  /** A new table version is in the state: draw it, and set up the player's shot if it is theirs. */
  shown() {
    const v = this.state.view;
    this.placement = null;
    this.notice = null;
    this.theirAim = null;
    this.match.confirming = false;
    this.view3d.setBalls(v.state.balls);
    this.session.beat(this.mine !== null && v.status === "playing");
    const shooting = this.state.turnOf(this.me) === "shot";
    const shot = shooting ? this.state.shot : null;
    showDeclarations($("extras"), shot);
    this.blocked = false;
    // A called pocket is ringed on the table as soon as it is chosen.
    this.view3d.markPocket(null);
    $("extras").querySelector('select[name="call"]')?.addEventListener("change", (e) => this.view3d.markPocket(e.target.value || null));
    this.view3d.setTargets(shot ? shot.targets : null);
    this.view3d.showRegion(shot?.place ?? null);
    this.controls.setEnabled(shot ? v.next.cue_ball : null, { placing: shot?.place ?? null });
    if (shot) {
      this.ensureCueBall();
      const aimed = aimAtTarget(this.view3d, v.next.cue_ball, shot.targets);
      this.blocked = aimed?.clear === false; // no straight line to a legal ball from here
      if (aimed) this.controls.set({ heading: aimed.heading });
    }
    this.render();
    this.practice?.shown();
    // /practice/{game} opens the player's running practice or a new one: once this one is
    // over, the address becomes the table's own, so that a reload shows it, replays and all.
    if (v.status === "over" && location.pathname.startsWith("/practice/")) history.replaceState(null, "", `/table/${v.id}`);
    countShown(v.version);
  }

  /** In a match, let the opponent and spectators watch the player to shoot line up (while the
   *  controls are live: not once the shot is on its way, whose outcome ends the turn). */
  shareAim() {
    if (!this.controls?.enabled || this.state.view?.mode !== "match" || this.state.turnOf(this.me) !== "shot") return;
    this.aimShare.offer(this.controls.aim, this.placement);
  }

  /** The aim of the player to shoot, drawn for the others: where the cue ball is placed and the
   *  cue along the line (as sent: the server passes it on unchecked, and nothing is played). */
  showTheirAim(message) {
    const v = this.state.view;
    if (this.shooter !== null || message.seat === this.mine || v.version !== message.version || !v.next) return;
    const cue = v.next.cue_ball;
    if (message.place) this.view3d.setBalls({ ...v.state.balls, [cue]: message.place });
    this.view3d.setAim(cue, message);
    this.theirAim = message;
  }

  /** Draw everything from the state (and the player's work in progress). */
  render() {
    const v = this.state.view;
    if (!v) return;
    const mine = this.mine;
    const turn = this.shooter === null ? this.state.turnOf(this.me) : null;
    this.showStatus();
    showScoreboard($("players"), v);
    $("choices").replaceChildren(...(turn === "choice" ? v.next.options : []).map((o) => button(optionWords(o), () => this.send({ option: o }))));
    // Spectators watch: no cue, no stroke controls; nor before the match starts or once over,
    // nor while a practice position is set up (its editor holds the table).
    const editing = Boolean(this.practice?.editing);
    for (const id of ["controls", "keys"]) $(id).hidden = editing || mine === null || v.status !== "playing" || turn === "choice";
    // The aim view looks along the cue: without one to aim the table is seen from above.
    $("view-toggle").hidden = editing || turn !== "shot";
    this.actions(mine);
  }

  showStatus() {
    const v = this.state.view;
    const refusal = $("refusal");
    refusal.hidden = !this.notice;
    refusal.textContent = this.notice ?? "";
    if (this.practice?.editing) {
      // Nothing is played while a position is set up: no ball-in-hand or contact words.
      $("hint").textContent = "";
      $("contact").hidden = true;
      $("status").textContent = EDITING_WORDS;
      return;
    }
    $("hint").textContent = this.handWords();
    this.showContact();
    if (this.shooter !== null) {
      $("status").textContent = `${seatName(v, this.shooter)} shoots...`;
      return;
    }
    if (v.status === "over" && v.winner != null) {
      $("status").textContent = `Match over. ${resultWords(v)} ${scoreWords(v)}`;
      return;
    }
    if (v.status === "open") {
      // Nothing is played before the opponent comes: only what to do about it.
      const lobby = v.options.private ? "" : ", or wait for a player from the lobby";
      const gone = `${seatName(v, 0)} has left this table: it waits for them to come back.`;
      const visit = v.presence[0] ? `Join this table to play ${seatName(v, 0)}.` : gone;
      const invite = this.mine === null ? visit : `Send this table's link to your opponent${lobby}.`;
      const waits = this.mine !== null || v.presence[0] ? nextWords(v) : "";
      $("status").textContent = [this.notice, waits, invite].filter(Boolean).join(" ");
      return;
    }
    const words = this.state.last ? outcomeWords(v, this.state.last) : "";
    $("status").textContent = [this.notice, words, nextWords(v), scoreWords(v)].filter(Boolean).join(" ");
  }

  /** What to do with the cue ball in hand, for the player who has it (beside the status, which
   *  every player and spectator reads alike). */
  handWords() {
    const place = this.shooter === null && this.state.turnOf(this.me) === "shot" ? this.state.shot?.place : null;
    if (!place) return "";
    return `Drag the cue ball (or Alt + arrow keys) to place it ${REGION_WORDS[place] ?? place}, in the shaded area.`;
  }

  /** The aim line's first ball, and whether the server lists it as a legal first contact. */
  showContact() {
    const contact = this.view3d?.contact;
    const box = $("contact");
    box.hidden = !contact || contact.legal === null;
    if (box.hidden) return;
    box.className = `contact ${contact.legal ? "legal" : "foul"}`;
    const legal = [...new Set(this.state.shot.targets.map(ballWords))].slice(0, 3).join(" or ");
    const blocked = this.blocked ? ` No straight line to ${legal} is clear from here: go off a cushion.` : "";
    box.textContent = contact.legal ? `Aiming at ${ballWords(contact.ball)}: a legal first contact.` : `Aiming at ${ballWords(contact.ball)}: hitting it first is a foul (hit ${legal}).${blocked}`;
  }

  tick() {
    // (Also once the gone player is back, or the match is over: the banner goes.)
    if (this.state.goneSeat() >= 0 || this.goneShown) {
      this.presenceBanner();
      const claim = this.state.claimable();
      if (claim !== this.claimShown) this.actions(this.mine);
      this.claimShown = claim;
    }
    showClock(this.state.view);
  }

  /** With the cue ball in hand and off the table, put it on a free place of the region. */
  ensureCueBall() {
    const v = this.state.view;
    const cue = v.next.cue_ball;
    if (v.state.balls[cue]) return;
    const p = freePlace(this.view3d.table, this.state.shot.place, v.state.balls, cue);
    if (p) this.place(p);
  }

  /** Move the cue ball in hand to p: kept in the region the server allows (and so on the
   *  table), and next to, not on, a ball it would overlap. */
  place(p) {
    const v = this.state.view;
    const t = this.view3d.table;
    const region = this.state.shot?.place;
    if (!region) return;
    const cue = v.next.cue_ball;
    const now = this.view3d.ballAt(cue);
    let at = keepInRegion(t, region, now && inRegion(t, region, now) ? now : usualSpot(t, region), p);
    if (overlap(t, v.state.balls, cue, at)) at = freePlace(t, region, v.state.balls, cue, at);
    if (!at) return;
    this.placement = at;
    this.blocked = false; // (from elsewhere a straight line may be clear)
    this.view3d.setBalls({ ...v.state.balls, [cue]: at });
    this.controls.show();
  }

  async strike(aim) {
    this.releasedAt = performance.now();
    const v = this.state.view;
    const cue = v.next.cue_ball;
    const missing = missingDeclaration($("extras"));
    const blocker = this.placement && overlap(this.view3d.table, v.state.balls, cue, this.placement);
    if (missing || blocker) {
      // Not sent: the referee would refuse it. The controls stay as they were, aim and all.
      this.controls.setEnabled(cue, { placing: this.state.shot?.place ?? null });
      this.notice = missing ? missing.words : `The cue ball cannot be placed on ${ballWords(blocker.id)}.`;
      this.render();
      missing?.input.focus();
      return;
    }
    const round = (x) => Number(x.toFixed(3));
    const strike = { ball: cue, speed: round(aim.speed), heading: round(aim.heading), elevation: aim.elevation, a: round(aim.a), b: round(aim.b) };
    const input = { strike, ...readDeclarations($("extras")) };
    if (this.placement) input.place = this.placement;
    this.aimShare.cancel();
    await this.aimShare.settled();
    await this.send(input);
  }

  /** Send an intent. Accepted, the status waits for the referee's decision; refused, it says
   *  why in the server's words (and code) until the next action, the shot left as it was. */
  async send(input) {
    this.notice = null;
    hooks.sending = true;
    try {
      this.sentShot = shotId();
      await this.session.intent(input, this.sentShot);
    } catch (e) {
      this.refused(e);
      if (e.code === "stale_version") await this.session.resync();
      else if (this.state.turnOf(this.me) === "shot") this.controls.setEnabled(this.state.view.next.cue_ball, { placing: this.state.shot?.place ?? null });
    } finally {
      hooks.sending = false;
    }
  }

  refused(e) {
    this.notice = `Refused (${e.code ?? "error"}): ${e.message.replace(/\.?$/, ".")}`;
    this.render();
  }

  actions(mine) {
    const v = this.state.view;
    const list = [];
    if (mine === null && v.status === "open" && v.presence[0]) list.push(button("Join this table", () => this.join(), "primary"));
    if (mine === null && v.mode !== "practice" && v.status === "playing") {
      list.push(Object.assign(document.createElement("p"), { className: "share muted", textContent: "You are watching this match." }));
    }
    if (v.options.private && v.status === "open" && mine !== null) {
      // The link is the invitation: the table is in no lobby list.
      const share = Object.assign(document.createElement("p"), { className: "share", id: "invite" });
      const link = Object.assign(document.createElement("a"), { href: `/table/${v.id}`, textContent: `${location.origin}/table/${v.id}` });
      share.append("Private table: send this link to your opponent ", link);
      list.push(share);
    }
    if (v.mode !== "practice") {
      const copy = () => {
        navigator.clipboard?.writeText(`${location.origin}/table/${v.id}`);
        this.banner("Link copied", 1500);
      };
      list.push(button("Copy link", copy));
    }
    $("actions").replaceChildren(...list);
    this.match.show($("match"), mine);
    $("chat").hidden = v.mode === "practice";
  }

  async join() {
    this.me = await ensurePlayer();
    await this.match.noteRating(this.state.view.game); // (a visitor had no rating to note)
    try {
      await this.session.action("join");
    } catch (e) {
      this.refused(e);
    }
  }

  chatButtons() {
    const say = async (code) => {
      this.me ??= await ensurePlayer();
      this.session.action("messages", { message: code }).catch((e) => this.banner(e.message, 2000));
    };
    $("chat").replaceChildren(...Object.entries(QUICK_MESSAGES).map(([code, words]) => button(words, () => say(code))));
  }

  presenceBanner() {
    const gone = this.state.goneSeat();
    const shown = this.goneShown;
    this.goneShown = gone >= 0;
    if (gone < 0) return shown && this.banner(null);
    const until = this.state.grace[gone];
    const left = until ? Math.max(0, Math.ceil(until - Date.now() / 1000)) : null;
    const wait = left ? ` (the win may be claimed in ${left} s)` : left === 0 ? " (the win may be claimed)" : "";
    this.banner(`${seatName(this.state.view, gone)} disconnected${wait}`);
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
