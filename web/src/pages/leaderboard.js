// /leaderboard/{game}: the game's highest breaks (GET /api/leaderboard/{game}, kept live from
// the `public-leaderboard` channel), each naming its player (a link to the profile) and opening
// its replay; and a form to claim a break from a game record, which the server replays and
// checks before it enters. A claim is made as a player (its token): the stored one if it has
// the name typed, else a new guest of that name.
import { currentPlayer, get, post, register, storedPlayer } from "../net/api.js";
import { KIND, LEADERBOARD } from "../net/protocol.js";
import { Subscription } from "../net/relay.js";
import { GAME_NAMES, GAMES } from "../lib/looks.js";
import { playerLink } from "../lib/players.js";

const $ = (id) => document.getElementById(id);
const SOURCES = { match: "played here: a match", practice: "played here: practice", claim: "submitted record, replayed here" };

function cell(text) {
  const td = document.createElement("td");
  td.textContent = text;
  return td;
}

function show(breaks) {
  const body = $("board").querySelector("tbody");
  body.replaceChildren();
  breaks.forEach((b, i) => {
    const row = document.createElement("tr");
    const replay = document.createElement("td");
    if (b.replay) {
      const a = document.createElement("a");
      a.href = `/replay/${b.replay}`;
      a.textContent = "Watch";
      replay.append(a);
    }
    const name = cell("");
    name.append(playerLink({ id: b.player ?? "", name: b.name }));
    row.append(cell(String(i + 1)), name, cell(String(b.score)), cell(SOURCES[b.source] ?? b.source), replay);
    body.append(row);
  });
  const n = breaks.length;
  $("board-status").textContent = n ? `${n} break${n === 1 ? "" : "s"}` : "No breaks yet: be the first.";
}

/** What the board ranks, in words, from the server's `ranks` (shown under the title). */
function showRanks(ranks) {
  const parts = [];
  if (ranks.reds) parts.push(`${ranks.reds} reds`);
  if (ranks.target) parts.push(`games to ${ranks.target} points`);
  if (ranks.size) parts.push(`the ${ranks.size} ft table`);
  const what = parts.length ? `${parts.join(", ")}, ` : "";
  const p = Object.assign(document.createElement("p"), { className: "muted", id: "ranks" });
  p.textContent = `Ranked: ${what}from the game's own rack. Breaks at other options or from set-up practice positions keep their replays but are not ranked.`;
  $("title").after(p);
}

async function claim(game) {
  const verdict = $("claim-verdict");
  verdict.className = "";
  verdict.textContent = "Checking the record...";
  try {
    const file = $("claim-file").files[0];
    const text = file ? await file.text() : $("claim-record").value;
    const record = JSON.parse(text);
    const name = $("claim-name").value.trim();
    const me = await currentPlayer();
    if (!me || me.name !== name) await register(name);
    const answer = await post("/api/leaderboard/claims", { game, record, score: Number($("claim-score").value) });
    verdict.textContent = `Accepted: a break of ${answer.entry.score} by ${answer.entry.name}.`;
    show((await get(`/api/leaderboard/${game}`)).breaks);
  } catch (e) {
    verdict.className = "error";
    verdict.textContent = e instanceof SyntaxError ? "That is not a JSON record." : `Refused: ${e.message}`;
  }
}

async function main() {
  const game = location.pathname.split("/")[2];
  document.title = `billiards: ${GAME_NAMES[game]} leaderboard`;
  $("title").textContent = `Highest breaks: ${GAME_NAMES[game]}`;
  for (const g of GAMES) {
    const a = document.createElement("a");
    a.href = `/leaderboard/${g}`;
    a.className = g === game ? "button primary" : "button";
    a.textContent = GAME_NAMES[g];
    $("game-links").append(a);
  }
  const me = storedPlayer();
  if (me) $("claim-name").value = me.name;
  $("claim-form").addEventListener("submit", (e) => {
    e.preventDefault();
    claim(game);
  });
  const board = await get(`/api/leaderboard/${game}`);
  showRanks(board.ranks);
  show(board.breaks);
  new Subscription(LEADERBOARD, { onMessage: (m) => m.kind === KIND.LEADERBOARD && m.game === game && show(m.breaks) });
}

main().catch((e) => {
  $("board-status").textContent = `Could not load the leaderboard: ${e.message}`;
});
