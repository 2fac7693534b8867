// /replay/{id}: shots played again, with pause, step, speed and a share link that opens at a
// given shot (`?shot=N`). The browser runs no physics, so it animates the outcomes the server
// published on the table's channel (which the relay keeps: its last 100 messages, for an hour):
// - a rack's replay (24 hex digits, GET /api/replays/{id}): the outcomes of that rack, the last
//   of which names the replay; a replay whose outcomes the relay no longer holds (or a claimed
//   break, played on no table) can be listed but not animated;
// - a table (20 hex digits): its shots so far, and each new one as it is played.
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

/** Where each ball on the table rests when a shot is over. */
function endPositions(trajectory) {
  const out = {};
  for (const [id, segments] of Object.entries(trajectory.balls)) {
    const last = segments[segments.length - 1];
    if (last[1] !== "pocketed") out[id] = [last[2], last[3]];
  }
  return out;
}

class ReplayPage {
  /** view: {game, mode, seats, state} of the table the shots were played on. */
  constructor(id, view, table) {
    this.id = id;
    this.view = view;
    this.shots = [];
    this.current = -1; // the shot shown (animating or finished)
    this.playing = true;
    this.speed = 1;
    this.view3d = new TableView($("table"), table, view.game);
    diagnostics.balls = () => this.view3d.drawnBalls();
    const wanted = Number(new URLSearchParams(location.search).get("shot"));
    this.startAt = Number.isInteger(wanted) && wanted > 0 ? wanted - 1 : 0;
    this.bind();
    this.say("Waiting for the table's shots...");
  }

  /** Add shots (outcomes with a trajectory) in the order played. */
  add(messages) {
    for (const message of messages) {
      if (!message.trajectory || this.shots.some((s) => s.version === message.version)) continue;
      this.shots.push(message);
      diagnostics.shots = this.shots.length;
      this.listShot(this.shots.length - 1);
    }
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
    // After a rack's last shot the state is already the next rack's: show where the balls
    // came to rest instead.
    this.view3d.setBalls(shot.decision?.over ? endPositions(shot.trajectory) : shot.state.balls);
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

/** A rack's outcomes: the `count` outcomes that end with the one naming `replayId`. */
function rackOutcomes(messages, replayId, count) {
  const outcomes = messages.filter((m) => m.kind === "outcome").sort((a, b) => a.version - b.version);
  const end = outcomes.findIndex((m) => m.replay === replayId);
  return end < 0 ? null : outcomes.slice(Math.max(0, end - count + 1), end + 1);
}

/** How long to wait for the relay's buffered messages before saying a rack is not there. */
const BUFFER_WAIT_MS = 4000;

async function openRack(id, tables) {
  const replay = await get(`/api/replays/${id}`);
  const table = replay.table ? await get(`/api/tables/${replay.table}`) : null;
  // Outcomes name table seats (the record's players are the breaker first).
  const seats = table?.seats ?? replay.players;
  const view = { game: replay.game, mode: table?.mode ?? "match", seats };
  const page = new ReplayPage(id, view, tables[replay.game]);
  page.say(`Rack ${replay.rack} of ${replay.game}: loading its shots...`);
  if (!table) {
    page.say("This break was claimed from a record: its shots were played on no table, so there is nothing to animate.");
    return page;
  }
  const seen = [];
  let found = false;
  const subscription = new Subscription(table.channel, {
    onMessage: (m) => {
      if (found) return;
      seen.push(m);
      const shots = rackOutcomes(seen, id, replay.record.inputs.length);
      if (shots) {
        found = true;
        subscription.close();
        page.add(shots);
      }
    },
  });
  setTimeout(() => {
    if (found) return;
    subscription.close();
    page.say("The shots of this rack are no longer kept on its table's channel.");
  }, BUFFER_WAIT_MS);
  return page;
}

async function openTable(id, tables) {
  const view = await get(`/api/tables/${id}`);
  const page = new ReplayPage(id, view, tables[view.game]);
  page.view3d.setBalls(view.state.balls);
  new Subscription(view.channel, { onMessage: (m) => m.kind === "outcome" && page.add([m]) });
  return page;
}

async function main() {
  const id = location.pathname.split("/")[2];
  const tables = await fetch("/web/tables").then((r) => r.json());
  const page = await (id.length === 24 ? openRack(id, tables) : openTable(id, tables));
  document.title = `billiards: replay (${page.view.game})`;
  const box = $("players");
  for (const seat of [0, 1]) {
    const name = document.createElement("span");
    name.textContent = playerName(page.view, seat);
    box.append(name, document.createElement("span"));
  }
  // The replay shows the table from above, where every ball can be followed.
  page.view3d.setMode("top");
  $("view-toggle").textContent = "Aim view";
}

main().catch((e) => {
  $("status").textContent = `Could not open the replay: ${e.message}`;
});
