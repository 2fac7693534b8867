// /replay/{id}: shots played again, with pause, step, speed and a share link that opens at a
// given shot (`?shot=N`). The browser runs no physics:
// - a rack's replay (24 hex digits): GET /api/replays/{id}/shots, every input's outcome, which
//   the server computes by replaying the record (so claimed breaks and old racks play too);
// - a table (20 hex digits): the outcomes published on its channel (its shots so far, from the
//   relay's buffer, and each new one as it is played).
import { ApiError, get } from "../net/api.js";
import { GAME_NAMES } from "../lib/looks.js";
import { KIND } from "../net/protocol.js";
import { Subscription } from "../net/relay.js";
import { nameElement } from "../play/profile.js";
import { TableSounds } from "../play/sound.js";
import { playedWords, playerName, rackUnit } from "../play/words.js";
import { Animation } from "../three/animate.js";
import { TableScene } from "../three/view.js";
import { tableFor } from "../play/tables.js";

const $ = (id) => document.getElementById(id);

/** Diagnostics the browser tests read (as on the play page). */
const diagnostics = { shown: -1, shots: 0 };
window.billiards = diagnostics;
const sounds = new TableSounds();
diagnostics.sound = () => sounds.stats();

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
    this.view3d = new TableScene($("table"), table, view.game);
    diagnostics.balls = () => this.view3d.drawnBalls();
    const wanted = Number(new URLSearchParams(location.search).get("shot"));
    this.startAt = Number.isInteger(wanted) && wanted > 0 ? wanted - 1 : 0;
    this.bind();
    this.say("Waiting for the table's shots...");
  }

  /** Add inputs in the order played: {key, seat, input, decision, trajectory, rest} (`rest`:
   * where the balls stand after it). Shots and choices (a choice moves nothing: it is told);
   * an input the engine refused, which changed nothing, is left out. */
  add(shots) {
    for (const shot of shots) {
      const played = shot.trajectory || shot.input.option;
      if (!played || this.shots.some((s) => s.key === shot.key)) continue;
      this.shots.push(shot);
      diagnostics.shots = this.shots.length;
      this.listShot(this.shots.length - 1);
    }
    if (this.shotWords) this.sayShot(this.shotWords.i, this.shotWords.words);
    const next = this.current < 0 ? this.startAt : this.current + 1;
    if (this.playing && !this.animation && next < this.shots.length) this.show(next);
  }

  /** How many shots (not choices) the inputs up to input i hold. */
  shotsTo(i) {
    return this.shots.slice(0, i + 1).filter((s) => s.trajectory).length;
  }

  listShot(i) {
    const shot = this.shots[i];
    const item = document.createElement("li");
    // Shots are numbered; a choice is told between them, unnumbered.
    if (shot.trajectory) item.value = this.shotsTo(i);
    else item.style.listStyleType = "none";
    const link = document.createElement("a");
    link.href = `?shot=${i + 1}`;
    link.textContent = playedWords(this.view, shot);
    link.addEventListener("click", (e) => {
      e.preventDefault();
      this.show(i);
    });
    item.append(link);
    $("shots").append(item);
  }

  /** Play shot i from its start (paused at its start if the replay is paused); a choice is
   *  only told. */
  show(i) {
    this.animation?.stop();
    this.animation = null;
    this.current = i;
    const shot = this.shots[i];
    if (!shot.trajectory) return this.finished(i);
    this.sayShot(i, `${playerName(this.view, shot.seat)} plays.`);
    this.animation = new Animation(this.view3d, shot.trajectory, {
      speed: this.speed,
      onDone: () => this.finished(i),
      onEvent: (type, speed) => sounds.play(type, speed),
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
    this.view3d.setBalls(shot.rest);
    this.sayShot(i, playedWords(this.view, shot));
    diagnostics.shown = i;
    if (this.playing && i + 1 < this.shots.length) setTimeout(() => this.current === i && !this.animation && this.show(i + 1), 600 / this.speed);
  }

  /** "Shot k of n: words" (a choice: "After shot k of n: words"), counting shots, not
   *  choices, and said again with the new count as more shots come in. */
  sayShot(i, words) {
    this.shotWords = { i, words };
    const of = this.shotsTo(this.shots.length - 1);
    const where = this.shots[i].trajectory ? "Shot" : "After shot";
    this.say(`${where} ${this.shotsTo(i)} of ${of}: ${words}`);
  }

  say(text) {
    $("status").textContent = text;
  }

  bind() {
    sounds.bindToggle($("sound"));
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

/** How long to wait before asking again while the server computes another replay. */
const BUSY_RETRY_MS = 1000;

/** GET /api/replays/{id}/shots?page=N, asking again while the server is busy (429). */
async function shotsPage(id, page) {
  for (;;) {
    try {
      return await get(`/api/replays/${id}/shots?page=${page}`);
    } catch (e) {
      if (!(e instanceof ApiError) || e.code !== "rate_limited") throw e;
      await new Promise((resolve) => setTimeout(resolve, BUSY_RETRY_MS));
    }
  }
}

/** Every shot of a replay: its pages in order, each naming the next. */
async function replayShots(id) {
  const shots = [];
  for (let page = 0; page !== null; ) {
    const answer = await shotsPage(id, page);
    shots.push(...answer.shots);
    page = answer.next;
  }
  return { shots };
}

/** The table a replay was played at, while the server still keeps it (a finished table is
 *  dropped a day after its end), else null. */
async function tableOf(replay) {
  if (!replay.table) return null;
  try {
    return await get(`/api/tables/${replay.table}`);
  } catch (e) {
    if (e instanceof ApiError && e.code === "not_found") return null;
    throw e;
  }
}

/** The names a replay's shots are told with: its seats; a replay with one person in it (a
 *  practice rack, a claimed break) is that person's, whichever side a shot was played from. */
function replayView(replay, table) {
  const people = replay.players.filter(Boolean);
  if (people.length === 1) return { game: replay.game, mode: "practice", seats: [people[0], null] };
  return { game: replay.game, mode: table?.mode ?? "match", seats: replay.players };
}

/** What the replay is, above its shots: the rack and game, and for a rack the match did not
 *  finish (its last state is not over) why, as far as the table, while kept, says. */
function aboutWords(replay, table, shots) {
  const unit = rackUnit(replay.game);
  const what = `${unit.charAt(0).toUpperCase()}${unit.slice(1)} ${replay.rack} of ${GAME_NAMES[replay.game] ?? replay.game}.`;
  const last = shots[shots.length - 1];
  if (!last || last.state.over) return what;
  const loser = table?.winner != null ? playerName(table, 1 - table.winner) : null;
  let why = "the match ended during it";
  if (table?.mode === "practice") why = "the practice was ended here";
  else if (loser && table.ended === "resigned") why = `${loser} resigned here`;
  else if (loser && table.ended === "claimed") why = `${loser} left and the win was claimed`;
  return `${what} Not finished: ${why}.`;
}

async function openRack(id, tables) {
  const replay = await get(`/api/replays/${id}`);
  const table = await tableOf(replay);
  const page = new ReplayPage(id, replayView(replay, table), tableFor(tables, replay.game, replay.record.setup.size));
  page.say(`Rack ${replay.rack} of ${replay.game}: loading its shots...`);
  const { shots } = await replayShots(id);
  $("about").textContent = aboutWords(replay, table, shots);
  // The replay's states are the rack's own, its last one where the rack ended.
  page.add(shots.map((s, i) => ({ key: i, seat: s.player, input: s.input, decision: s.decision, trajectory: s.trajectory, rest: s.state.balls })));
  return page;
}

/** A table's outcome as a shot: after a rack's last shot the state is already the next
 * rack's, so it rests where the balls came to rest. */
function outcomeShot(m) {
  const rest = m.decision?.over && m.trajectory ? endPositions(m.trajectory) : m.state.balls;
  return { key: m.version, seat: m.seat, input: m.input, decision: m.decision, trajectory: m.trajectory, rest };
}

async function openTable(id, tables) {
  const view = await get(`/api/tables/${id}`);
  const page = new ReplayPage(id, view, tableFor(tables, view.game, view.options.size));
  page.view3d.setBalls(view.state.balls);
  new Subscription(view.channel, { onMessage: (m) => m.kind === KIND.OUTCOME && page.add([outcomeShot(m)]) });
  return page;
}

async function main() {
  const id = location.pathname.split("/")[2];
  const tables = await fetch("/web/tables").then((r) => r.json());
  const page = await (id.length === 24 ? openRack(id, tables) : openTable(id, tables));
  document.title = `billiards: replay (${page.view.game})`;
  const box = $("players");
  const { view } = page;
  for (const seat of [0, 1]) {
    const player = view.seats[view.mode === "practice" ? 0 : seat]; // practice: one person
    const name = document.createElement("span");
    name.append(nameElement(player, playerName(view, seat)));
    box.append(name, document.createElement("span"));
  }
  // The replay shows the table from above, where every ball can be followed.
  page.view3d.setMode("top");
  $("view-toggle").textContent = "Aim view";
}

main().catch((e) => {
  $("status").textContent = `Could not open the replay: ${e.message}`;
});
