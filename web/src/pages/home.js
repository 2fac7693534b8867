// The home page and lobby: a name, then per game quick match, a game against the bot, practice;
// a table with options (a private one gives a link to send); the lobby's open tables and games in
// progress, live from the `public-lobby` channel.
import { call, currentPlayer, get, post, register, storedPlayer } from "../net/api.js";
import { ensurePlayer, showWho } from "../net/identity.js";
import { Subscription } from "../net/relay.js";
import { GAME_NAMES, GAMES } from "../lib/looks.js";
import { LOBBY, playerChannel, QUICK_POLL_MS, SIZED_GAMES, TABLE_SIZE, TABLE_SIZES } from "../net/protocol.js";
import { BOT_LEVELS, DEFAULT_BOT } from "../play/words.js";

const $ = (id) => document.getElementById(id);

/** A name refused by the server, in words a player can act on (a malformed one is refused
 *  with the validator's pattern, which no player should have to read). */
function nameRefusal(err) {
  if (err.code === "bad_request") return "Use 1 to 24 letters, digits, spaces, dots, dashes or underscores, with no space at either end.";
  if (err.code === "name_taken") return "Someone online has that name: choose another.";
  return err.message;
}

function error(e) {
  $("home-error").textContent = e ? e.message : "";
}

function el(tag, text, className) {
  const node = document.createElement(tag);
  if (text != null) node.textContent = text;
  if (className) node.className = className;
  return node;
}

function go(tableId) {
  location.href = `/table/${tableId}`;
}

let waiting = null;

async function quickMatch(game, button) {
  error(null);
  const me = await ensurePlayer();
  if (waiting) return;
  const status = await post("/api/quick", { game });
  if (status.status === "paired") return go(status.table);
  button.textContent = "Waiting for an opponent... (cancel)";
  waiting = new Subscription(playerChannel(me.id), {
    onMessage: (m) => m.kind === "paired" && go(m.table),
  });
  // The server keeps a request only while it is polled (a closed page is never paired); the
  // poll also finds a pairing whose message was missed.
  setInterval(async () => {
    const now = await get("/api/quick").catch(() => null);
    if (now?.status === "paired") go(now.table);
  }, QUICK_POLL_MS);
  button.onclick = async () => {
    await call("DELETE", "/api/quick").catch(() => {});
    location.reload();
  };
}

function gameCards() {
  const grid = $("games");
  for (const game of GAMES) {
    const card = el("div", null, "card");
    card.append(el("h2", GAME_NAMES[game]));
    const row = el("div", null, "row");
    const quick = el("button", "Quick match", "primary");
    quick.type = "button";
    quick.onclick = () => quickMatch(game, quick).catch(error);
    const level = el("select", null, "bot-level");
    level.setAttribute("aria-label", `${GAME_NAMES[game]}: the bot's level`);
    for (const [value, words] of Object.entries(BOT_LEVELS)) level.append(new Option(words, value, false, value === DEFAULT_BOT));
    const bot = el("button", "Play the bot");
    bot.type = "button";
    bot.onclick = () =>
      ensurePlayer()
        .then(() => post("/api/tables", { game, mode: "bot", bot: level.value }))
        .then((v) => go(v.id))
        .catch(error);
    const practice = el("a", "Practice", "button");
    practice.href = `/practice/${game}`;
    const board = el("a", "Leaderboard", "button");
    board.href = `/leaderboard/${game}`;
    row.append(quick, level, bot, practice, board);
    card.append(row);
    grid.append(card);
  }
  const select = $("create-game");
  for (const game of GAMES) select.append(new Option(GAME_NAMES[game], game));
}

/** The create form's table size select, shown for the games played on tables of several sizes;
 *  returns what it adds to the create request. */
function sizeSelect() {
  const game = $("create-game");
  const size = Object.assign(el("select"), { id: "size" });
  for (const feet of TABLE_SIZES) size.append(new Option(`${feet} ft`, String(feet), false, feet === TABLE_SIZE));
  const label = el("label", "Table ");
  label.append(size);
  game.after(label);
  const shown = () => (label.hidden = !SIZED_GAMES.includes(game.value));
  game.addEventListener("change", shown);
  shown();
  return () => (label.hidden ? {} : { size: Number(size.value) });
}

function showTables(tables, online) {
  $("online").textContent = online == null ? "" : `${online} player${online === 1 ? "" : "s"} online`;
  const body = $("tables").querySelector("tbody");
  body.replaceChildren();
  if (!tables.length) body.append(Object.assign(el("tr"), { innerHTML: '<td class="muted">No open tables right now.</td>' }));
  for (const t of tables) {
    const row = el("tr");
    const names = t.mode === "practice" ? `${t.seats[0]?.name ?? ""} (practice)` : t.seats.map((s) => s?.name ?? "(free seat)").join(" vs ");
    row.append(el("td", GAME_NAMES[t.game] ?? t.game), el("td", names), el("td", t.status === "open" ? "open" : `in progress, ${t.spectators} watching`));
    const cell = el("td");
    const link = el("a", t.status === "open" ? "Join" : "Watch", "button");
    link.href = `/table/${t.id}`;
    cell.append(link);
    row.append(cell);
    body.append(row);
  }
}

async function main() {
  gameCards();
  const sizeOf = sizeSelect();
  const stored = storedPlayer();
  if (stored) $("name").value = stored.name;
  ensurePlayerQuietly();
  $("name-form").addEventListener("submit", async (e) => {
    e.preventDefault();
    $("name-error").textContent = "";
    try {
      showWho(await register($("name").value.trim()));
    } catch (err) {
      $("name-error").textContent = nameRefusal(err);
    }
  });
  $("create-form").addEventListener("submit", async (e) => {
    e.preventDefault();
    error(null);
    try {
      await ensurePlayer();
      const view = await post("/api/tables", {
        game: $("create-game").value,
        race_to: Number($("race").value),
        shot_clock: Number($("clock").value),
        private: $("private").checked,
        ...sizeOf(),
      });
      go(view.id);
    } catch (err) {
      error(err);
    }
  });
  get("/api/tables")
    .then((list) => showTables(list.tables, null))
    .catch(error);
  new Subscription(LOBBY, {
    onMessage: (m) => m.kind === "lobby" && showTables(m.tables, m.players_online),
  });
}

async function ensurePlayerQuietly() {
  const me = await currentPlayer().catch(() => null);
  showWho(me);
  if (me) $("name").value = me.name;
}

main().catch(error);
