// /replay/{id}: a table's shots played again from the outcomes the server published on the
// table's channel (the relay keeps them; a new one is appended as it is played), with pause,
// step, speed and a share link that opens at a given shot (`?shot=N`).
import { get } from "../net/api.js";
import { Subscription } from "../net/relay.js";
import { decisionWords, playerName } from "../play/words.js";
import { Animation } from "../three/animate.js";
import { TableView } from "../three/view.js";

const $ = (id) => document.getElementById(id);

/** Diagnostics the browser tests read (as on the play page). */
const diagnostics = { shown: -1, shots: 0 };
window.billiards = diagnostics;

/** Where each ball stands when a shot starts: its first segment's position. */
function startPositions(trajectory) {
  return Object.fromEntries(Object.entries(trajectory.balls).map(([id, segments]) => [id, [segments[0][2], segments[0][3]]]));
}

class ReplayPage {
  constructor(id, view, table) {
    this.id = id;
    this.view = view;
    this.shots = [];
    this.current = -1; // the shot shown (animating or finished)
    this.playing = true;
    this.speed = 1;
    this.view3d = new TableView($("table"), table, view.game);
    this.view3d.setBalls(view.state.balls);
    diagnostics.balls = () => {
      const out = {};
      for (const ball of this.view3d.balls.keys()) {
        const p = this.view3d.ballAt(ball);
        if (p) out[ball] = p;
      }
      return out;
    };
    const wanted = Number(new URLSearchParams(location.search).get("shot"));
    this.startAt = Number.isInteger(wanted) && wanted > 0 ? wanted - 1 : 0;
    this.bind();
    this.say("Waiting for the table's shots...");
    this.subscription = new Subscription(view.channel, { onMessage: (m) => this.receive(m) });
  }

  receive(message) {
    if (message.kind !== "outcome" || !message.trajectory) return;
    if (this.shots.some((s) => s.version === message.version)) return;
    this.shots.push(message);
    this.shots.sort((a, b) => a.version - b.version);
    diagnostics.shots = this.shots.length;
    this.listShot(this.shots.length - 1);
    const next = this.current < 0 ? this.startAt : this.current + 1;
    if (this.playing && !this.animation && next < this.shots.length) this.show(next);
  }

  listShot(i) {
    const shot = this.shots[i];
    const item = document.createElement("li");
    const link = document.createElement("a");
    link.href = `?shot=${i + 1}`;
    link.textContent = decisionWords(this.view, shot.decision);
    link.addEventListener("click", (e) => {
      e.preventDefault();
      this.show(i);
    });
    item.append(link);
    $("shots").append(item);
  }

  /** Play shot i from its start (paused at its start if the replay is paused). */
  show(i) {
    this.animation?.stop();
    this.current = i;
    const shot = this.shots[i];
    this.say(`Shot ${i + 1} of ${this.shots.length}: ${playerName(this.view, shot.seat)} plays.`);
    this.animation = new Animation(this.view3d, shot.trajectory, {
      speed: this.speed,
      onDone: () => this.finished(i),
    });
    this.animation.paused = !this.playing;
    // The aim view looks along the shot, from behind the ball struck.
    this.view3d.cameraBall = shot.input.strike.ball;
    this.view3d.aim.heading = shot.input.strike.heading;
    this.view3d.shownMode = null; // place the camera afresh for this shot
    this.view3d.setBalls(startPositions(shot.trajectory));
    this.animation.play();
  }

  finished(i) {
    const shot = this.shots[i];
    this.animation = null;
    this.view3d.setBalls(shot.state.balls);
    this.say(`Shot ${i + 1} of ${this.shots.length}: ${decisionWords(this.view, shot.decision)}`);
    diagnostics.shown = i;
    if (this.playing && i + 1 < this.shots.length) setTimeout(() => this.current === i && !this.animation && this.show(i + 1), 600 / this.speed);
  }

  say(text) {
    $("status").textContent = text;
  }

  bind() {
    $("pause").addEventListener("click", () => {
      this.playing = !this.playing;
      $("pause").textContent = this.playing ? "Pause" : "Play";
      if (this.animation) this.animation.paused = !this.playing;
      else if (this.playing && this.current + 1 < this.shots.length) this.show(this.current + 1);
    });
    $("prev").addEventListener("click", () => this.shots.length && this.show(Math.max(0, this.current - 1)));
    $("next").addEventListener("click", () => {
      if (this.current + 1 < this.shots.length) this.show(this.current + 1);
    });
    $("speed").addEventListener("change", () => {
      this.speed = Number($("speed").value);
      if (this.animation) this.animation.speed = this.speed;
    });
    $("view-toggle").addEventListener("click", () => {
      const top = this.view3d.mode === "aim";
      this.view3d.setMode(top ? "top" : "aim");
      $("view-toggle").textContent = top ? "Aim view" : "Top view";
    });
    $("share").addEventListener("click", () => {
      const url = `${location.origin}/replay/${this.id}?shot=${Math.max(1, this.current + 1)}`;
      navigator.clipboard?.writeText(url).catch(() => {});
      $("shared").textContent = url;
    });
  }
}

async function main() {
  const id = location.pathname.split("/")[2];
  const [view, tables] = await Promise.all([get(`/api/tables/${id}`), fetch("/web/tables").then((r) => r.json())]);
  document.title = `billiards: replay (${view.game})`;
  const box = $("players");
  for (const seat of [0, 1]) {
    const name = document.createElement("span");
    name.textContent = playerName(view, seat);
    box.append(name, document.createElement("span"));
  }
  // The replay shows the table from above, where every ball can be followed.
  const page = new ReplayPage(id, view, tables[view.game]);
  page.view3d.setMode("top");
  $("view-toggle").textContent = "Aim view";
}

main().catch((e) => {
  $("status").textContent = `Could not open the replay: ${e.message}`;
});
