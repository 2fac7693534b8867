// The home page and lobby: a name, then per game its options, quick match, a game against the
// bot at a level (named, with the bot's rating in that game), practice; a table with options (a
// private one gives a link to send); the lobby's open tables and games in progress and who is
// online, live from the `public-lobby` channel; direct challenges, live from the player's own
// channel (lobby/challenges.js).
import { call, currentPlayer, get, post, register, storedPlayer } from "../net/api.js";
import { ensurePlayer, showWho } from "../net/identity.js";
import { Subscription } from "../net/relay.js";
import { GAME_NAMES, GAMES } from "../lib/looks.js";
import { GAME_OPTIONS, optionControls, optionWords, TABLE_OPTIONS } from "../lib/options.js";
import { playerLink } from "../lib/players.js";
import { KIND, LOBBY, playerChannel, QUICK_POLL_MS, QUICK_SHOT_CLOCK } from "../net/protocol.js";
import { BOT_LEVELS, DEFAULT_BOT } from "../play/words.js";
import { Challenges } from "../lobby/challenges.js";
import { challengeForm, showOnline } from "../lobby/online.js";

const $ = (id) => document.getElementById(id);

/** A name refused by the server, in words a player can act on (a malformed one is refused
 *  with the validator's pattern, which no player should have to read). */
function nameRefusal(err) {
  if (err.code === "bad_request") return "Use 1 to 24 letters, digits, spaces, dots, dashes or underscores, with no space at either end.";
  if (err.code === "name_taken") return "Someone online has that name: choose another.";
  return err.message;
}

/** The page's one line for a refusal (kept here: it moves about the page). */
const errorLine = $("home-error");

/** Show refusal `e` (null: none) where the player is looking: the page's one error line
 *  moves into the card of `near`, the control that failed (or into the corner box of
 *  challenges), and is scrolled into sight; without a control it stays where it was (at
 *  first the page's foot), scrolled into sight too. */
function error(e, near = null) {
  errorLine.textContent = e ? e.message : "";
  if (!e) return;
  const box = near?.closest(".card, .challenges");
  if (box && errorLine.parentElement !== box) box.append(errorLine);
  errorLine.scrollIntoView({ block: "nearest" });
}

/** error(e) shown beside `control`: for a promise's catch. */
const errorAt = (control) => (e) => error(e, control);

function el(tag, text, className) {
  const node = document.createElement(tag);
  if (text != null) node.textContent = text;
  if (className) node.className = className;
  return node;
}

function go(tableId) {
  location.href = `/table/${tableId}`;
}

/** What the page knows of its player once it has one: its channel's messages go to `listeners`
 *  (challenges, a quick match waiting). */
const session = { me: null, challenges: null, listeners: [] };

/** The lobby's last snapshot (LobbyMessage), drawn again once the page knows its player. */
let lobby = null;

function startSession(me) {
  if (session.me?.id === me.id) return;
  if (session.me) return location.reload(); // another name now: start again as it
  session.me = me;
  // The lobby's last snapshot was drawn for nobody: draw it again, the player's own name
  // marked "(you)" rather than offered a challenge.
  if (lobby) showLobby(lobby);
  session.challenges = new Challenges($("challenges"), me, go, error);
  session.listeners.push((m) => session.challenges.onMessage(m));
  new Subscription(playerChannel(me.id), { onMessage: (m) => session.listeners.forEach((f) => f(m)) });
  showNotificationOffer();
}

async function player() {
  const me = await ensurePlayer();
  startSession(me);
  return me;
}

let waiting = false;

async function quickMatch(game, options, button) {
  error(null);
  await player();
  if (waiting) return;
  const status = await post("/api/quick", { game, ...options });
  if (status.status === "paired") return go(status.table);
  waiting = true;
  button.textContent = "Waiting for an opponent... (cancel)";
  // The server keeps a request only while it is polled (a closed page is never paired). A
  // `paired` message (the channel may replay old ones) is checked against the server's answer.
  const poll = async () => {
    const now = await get("/api/quick").catch(() => null);
    if (now?.status === "paired") go(now.table);
  };
  session.listeners.push((m) => m.kind === KIND.PAIRED && poll());
  setInterval(poll, QUICK_POLL_MS);
  button.onclick = async () => {
    await call("DELETE", "/api/quick").catch(() => {});
    location.reload();
  };
}

/** The bots as /api/bots lists them, once it has answered. */
let bots = null;

/** A bot's rating in `game` (null: unrated, or /api/bots has not answered). */
function botRating(id, game) {
  return bots?.find((b) => b.id === id)?.ratings[game] ?? null;
}

/** A bot level in words, with its rating in `game` once /api/bots has answered. */
function botLabel(id, game) {
  if (!bots) return BOT_LEVELS[id];
  const rating = botRating(id, game);
  // In a few characters, as lichess writes a provisional rating: "1662?".
  return `${BOT_LEVELS[id]} · ${rating ? `${Math.round(rating.rating)}${rating.provisional ? "?" : ""}` : "unrated"}`;
}

/** Under a card's level select: the chosen bot's rating in the card's game, in words. */
function showBotRating(select) {
  const game = select.closest(".card").dataset.game;
  const rating = botRating(select.value, game);
  const provisional = rating?.provisional ? " (provisional)" : "";
  const words = rating ? `Rated ${Math.round(rating.rating)}${provisional} in ${GAME_NAMES[game]}.` : "Not rated yet in this game.";
  select.nextElementSibling.textContent = bots ? words : "";
}

function gameCard(game) {
  const card = el("div", null, "card");
  card.dataset.game = game;
  card.append(el("h2", GAME_NAMES[game]));
  const options = el("div", null, "row options");
  const read = optionControls(options, game, GAME_OPTIONS);
  const row = el("div", null, "row");
  const quick = el("button", "Quick match", "primary");
  quick.type = "button";
  quick.title = `Paired with the next player asking for the same options; ${QUICK_SHOT_CLOCK} s shot clock`;
  quick.onclick = () => quickMatch(game, read(), quick).catch(errorAt(quick));
  const level = el("select", null, "bot-level");
  level.setAttribute("aria-label", `${GAME_NAMES[game]}: the bot's level`);
  for (const id of Object.keys(BOT_LEVELS)) level.append(new Option(botLabel(id, game), id, false, id === DEFAULT_BOT));
  level.onchange = () => showBotRating(level);
  const rating = el("span", null, "muted bot-rating");
  const bot = el("button", "Play the bot");
  bot.type = "button";
  bot.onclick = () =>
    player()
      .then(() => post("/api/tables", { game, mode: "bot", bot: level.value, ...read() }))
      .then((v) => go(v.id))
      .catch(errorAt(bot));
  const practice = el("a", "Practice", "button");
  practice.href = `/practice/${game}`;
  const board = el("a", "Leaderboard", "button");
  board.href = `/leaderboard/${game}`;
  row.append(quick, level, rating, bot, practice, board);
  card.append(options, row);
  return card;
}

async function showBotRatings() {
  bots = (await get("/api/bots")).bots;
  for (const select of document.querySelectorAll("#games select.bot-level")) {
    const game = select.closest(".card").dataset.game;
    for (const option of select.options) option.textContent = botLabel(option.value, game);
    showBotRating(select);
  }
}

function createForm() {
  const select = $("create-game");
  for (const game of GAMES) select.append(new Option(GAME_NAMES[game], game));
  let read = optionControls($("create-options"), select.value, TABLE_OPTIONS);
  select.addEventListener("change", () => (read = optionControls($("create-options"), select.value, TABLE_OPTIONS)));
  $("create-form").addEventListener("submit", async (e) => {
    e.preventDefault();
    error(null);
    try {
      await player();
      const view = await post("/api/tables", { game: select.value, ...read(), private: $("private").checked });
      go(view.id);
    } catch (err) {
      error(err, $("create-form"));
    }
  });
}

function names(t) {
  const cell = el("td");
  if (t.mode === "practice") {
    cell.append(t.seats[0] ? playerLink(t.seats[0]) : "", " (practice)");
    return cell;
  }
  t.seats.forEach((s, i) => cell.append(i ? " vs " : "", s ? playerLink(s) : "(free seat)"));
  return cell;
}

function showTables(tables, online) {
  $("online").textContent = online == null ? "" : `${online} player${online === 1 ? "" : "s"} online`;
  const body = $("tables").querySelector("tbody");
  body.replaceChildren();
  if (!tables.length) body.append(Object.assign(el("tr"), { innerHTML: '<td class="muted">No open tables right now.</td>' }));
  for (const t of tables) {
    const row = el("tr");
    const game = [GAME_NAMES[t.game] ?? t.game, optionWords(t.game, t.options)].filter(Boolean).join(", ");
    row.append(el("td", game), names(t), el("td", t.status === "open" ? "open" : `in progress, ${t.spectators} watching`));
    const cell = el("td");
    const link = el("a", t.status === "open" ? "Join" : "Watch", "button");
    link.href = `/table/${t.id}`;
    cell.append(link);
    row.append(cell);
    body.append(row);
  }
}

function showLobby(m) {
  lobby = m;
  showTables(m.tables, m.players_online);
  // A refusal shows under the list and its challenge form (which is redrawn for each player:
  // the error line is kept out of it).
  const refused = errorAt($("people"));
  const challenge = (target) =>
    player()
      .then(() => challengeForm($("challenge-form"), target, (body) => session.challenges.send(body), refused))
      .catch(refused);
  showOnline($("people"), m.online, session.me, challenge);
}

/** Offer browser notifications of challenges while the player has not decided. */
function showNotificationOffer() {
  const button = $("notify");
  if (!("Notification" in window) || Notification.permission !== "default") return;
  button.hidden = false;
  button.onclick = () => Notification.requestPermission().finally(() => (button.hidden = true));
}

async function main() {
  for (const game of GAMES) $("games").append(gameCard(game));
  createForm();
  showBotRatings().catch(error);
  const stored = storedPlayer();
  if (stored) $("name").value = stored.name;
  ensurePlayerQuietly();
  $("name-form").addEventListener("submit", async (e) => {
    e.preventDefault();
    $("name-error").textContent = "";
    try {
      const me = await register($("name").value.trim());
      showWho(me);
      startSession(me);
    } catch (err) {
      $("name-error").textContent = nameRefusal(err);
    }
  });
  get("/api/tables")
    .then((list) => showTables(list.tables, null))
    .catch(errorAt($("tables")));
  new Subscription(LOBBY, { onMessage: (m) => m.kind === KIND.LOBBY && showLobby(m) });
}

async function ensurePlayerQuietly() {
  const me = await currentPlayer().catch(() => null);
  showWho(me);
  if (!me) return;
  $("name").value = me.name;
  startSession(me);
}

main().catch(error);
