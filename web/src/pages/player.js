// /player/{name}: who a player is here. The name is resolved by the server (GET
// /api/players/named/{name}: the player holding it now, or who held it last), then the profile
// (GET /api/players/{id}/profile): the rating in each game (provisional while RD > 110), a graph
// of each game's rating over the last rated matches (uPlot), recent matches with every rack's
// replay, best breaks, and whether the player is online or when it was last seen.
import uPlot from "uplot";
import { get, storedPlayer } from "../net/api.js";
import { showWho } from "../net/identity.js";
import { GAME_NAMES, GAMES } from "../lib/looks.js";
import { playerHref, playerLink } from "../lib/players.js";

const $ = (id) => document.getElementById(id);
const COLOURS = { nineball: "#e8b04a", eightball: "#5fbf7f", snooker: "#e0645a", three_cushion: "#6fa8ff" };
const ENDINGS = { racks: "", resigned: " (resigned)", claimed: " (claimed: opponent gone)" };

function el(tag, text, className) {
  const node = document.createElement(tag);
  if (text != null) node.textContent = text;
  if (className) node.className = className;
  return node;
}

function row(...cells) {
  const tr = el("tr");
  for (const cell of cells) tr.append(cell instanceof Node ? cell : el("td", String(cell)));
  return tr;
}

/** A table body's one line saying it is empty. */
function empty(body, text) {
  const cell = el("td", null, "muted");
  cell.colSpan = body.parentElement.querySelectorAll("th").length;
  cell.textContent = text;
  body.append(row(cell));
}

function td(...children) {
  const cell = el("td");
  cell.append(...children);
  return cell;
}

const when = (t) => new Date(t * 1000).toLocaleString([], { dateStyle: "medium", timeStyle: "short" });

/** "3 minutes ago", "2 days ago": how long since unix time `t`. */
function ago(t) {
  const s = Math.max(0, Date.now() / 1000 - t);
  const units = [["day", 86400], ["hour", 3600], ["minute", 60]];
  for (const [unit, size] of units) {
    if (s >= size) {
      const n = Math.floor(s / size);
      return `${n} ${unit}${n === 1 ? "" : "s"} ago`;
    }
  }
  return "just now";
}

function showSeen(p) {
  if (p.online) {
    $("seen").replaceChildren(el("span", "● ", "online-dot"), "online now");
  } else {
    $("seen").textContent = p.last_seen ? `last seen ${ago(p.last_seen)} (${when(p.last_seen)})` : "not seen lately";
  }
}

function showRatings(ratings) {
  const body = $("ratings").querySelector("tbody");
  body.replaceChildren();
  const played = GAMES.filter((g) => ratings[g]);
  if (!played.length) empty(body, "No rated matches yet.");
  for (const game of played) {
    const r = ratings[game];
    const rating = td(String(Math.round(r.rating)));
    if (r.provisional) rating.append(" ", el("span", "provisional", "provisional"));
    body.append(row(GAME_NAMES[game], rating, `± ${Math.round(r.deviation)}`, r.games));
  }
}

/** The graph's rating axis: the ratings shown with a margin (uPlot's own range starts at 0). */
function ratingRange(history) {
  const ratings = history.map((p) => p.rating);
  const [low, high] = [Math.min(...ratings), Math.max(...ratings)];
  const margin = Math.max(50, (high - low) * 0.1);
  return [Math.floor((low - margin) / 50) * 50, Math.ceil((high + margin) / 50) * 50];
}

/** The graph's time axis: the matches with a margin (a single match is not drawn over years). */
function timeRange(xs) {
  const margin = Math.max(60, (xs[xs.length - 1] - xs[0]) * 0.03);
  return [xs[0] - margin, xs[xs.length - 1] + margin];
}

/** The rating of each game over time: one series per game, drawn between its own matches. */
function showGraph(history) {
  const box = $("rating-graph");
  box.replaceChildren();
  if (!history.length) {
    box.append(el("p", "The graph starts with the first rated match.", "muted"));
    return null;
  }
  const games = GAMES.filter((g) => history.some((p) => p.game === g));
  const xs = history.map((p) => p.at);
  const data = [xs, ...games.map((g) => history.map((p) => (p.game === g ? p.rating : null)))];
  const axis = { stroke: "#9aa0a8", grid: { stroke: "#2b3038" }, ticks: { stroke: "#2b3038" } };
  const options = {
    width: Math.max(280, box.clientWidth - 8),
    height: 300,
    scales: { x: { time: true, range: timeRange(xs) }, y: { range: ratingRange(history) } },
    axes: [axis, { ...axis, label: "rating" }],
    series: [{ label: "date" }, ...games.map((g) => ({ label: GAME_NAMES[g], stroke: COLOURS[g], width: 2, spanGaps: true, points: { show: true } }))],
  };
  return new uPlot(options, data, box);
}

function replayLinks(replays) {
  const cell = el("td", null, "replay-links");
  replays.forEach((id, i) => {
    const a = el("a", replays.length === 1 ? "replay" : `rack ${i + 1}`);
    a.href = `/replay/${id}`;
    cell.append(a);
  });
  return cell;
}

function showMatches(matches) {
  const body = $("matches").querySelector("tbody");
  body.replaceChildren();
  if (!matches.length) empty(body, "No decided matches yet.");
  for (const m of matches) {
    const result = td(el("span", m.won ? "Won" : "Lost", m.won ? "won" : "lost"), ENDINGS[m.ended] ?? "");
    const change = m.rating_after - m.rating_before;
    const rating = `${Math.round(m.rating_after)} (${change >= 0 ? "+" : "−"}${Math.abs(change).toFixed(1)})`;
    body.append(row(when(m.at), GAME_NAMES[m.game] ?? m.game, td(playerLink(m.opponent)), result, m.score.join("–"), rating, replayLinks(m.replays)));
  }
}

function showBreaks(breaks) {
  const body = $("breaks").querySelector("tbody");
  body.replaceChildren();
  const games = GAMES.filter((g) => breaks[g]);
  if (!games.length) empty(body, "No breaks on the leaderboards yet.");
  for (const game of games) {
    const b = breaks[game];
    const link = el("a", "watch");
    if (b.replay) link.href = `/replay/${b.replay}`;
    body.append(row(GAME_NAMES[game], b.score, b.replay ? td(link) : ""));
  }
}

async function main() {
  showWho(storedPlayer());
  const name = decodeURIComponent(location.pathname.split("/")[2] ?? "");
  const player = await get(`/api/players/named/${encodeURIComponent(name)}`);
  // The name as its holder spells it (names that read the same are one name).
  if (player.name !== name) history.replaceState(null, "", playerHref(player.name));
  const p = await get(`/api/players/${player.id}/profile`);
  document.title = `billiards: ${p.player.name}`;
  $("player-name").textContent = p.player.name;
  showSeen(p);
  showRatings(p.ratings);
  showMatches(p.matches);
  showBreaks(p.best_breaks);
  const plot = showGraph(p.history);
  window.billiards = { profile: p, graph: plot };
}

main().catch((e) => {
  $("profile-error").textContent = e.code === "not_found" ? `No player here goes by that name. (${e.message})` : `Could not load the profile: ${e.message}`;
  window.billiards = { error: e.code ?? "error" };
});
