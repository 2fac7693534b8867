// Who is online, from the lobby's snapshots (LobbyMessage.online: each player and what it is
// doing), each name linking to its profile, with a button to challenge the player; and the
// form that chooses the game and options of a challenge.
import { GAME_NAMES, GAMES } from "../lib/looks.js";
import { optionControls, TABLE_OPTIONS } from "../lib/options.js";
import { playerLink } from "../lib/players.js";

const DOING_WORDS = { playing: "playing", waiting: "waiting for a quick match", online: "in the lobby or watching" };

function el(tag, text, className) {
  const node = document.createElement(tag);
  if (text != null) node.textContent = text;
  if (className) node.className = className;
  return node;
}

/** Fill list `box` with the players online; `challenge(player)` when a Challenge button is
 *  pressed (none for `me`, nor for a player at a table: a challenge needs both in the lobby). */
export function showOnline(box, online, me, challenge) {
  box.replaceChildren();
  if (!online.length) box.append(el("li", "Nobody else is here right now.", "muted"));
  for (const { player, doing, table } of online) {
    const item = el("li");
    item.dataset.player = player.id;
    item.append(playerLink(player), el("span", ` ${DOING_WORDS[doing] ?? doing}`, `muted doing ${doing}`));
    if (table) {
      const watch = el("a", "watch", "watch");
      watch.href = `/table/${table}`;
      item.append(" ", watch);
    }
    if (me && player.id === me.id) item.append(el("span", " (you)", "muted"));
    else if (doing !== "playing") {
      const button = el("button", "Challenge", "challenge-button");
      button.type = "button";
      button.setAttribute("aria-label", `Challenge ${player.name}`);
      button.onclick = () => challenge(player);
      item.append(" ", button);
    }
    box.append(item);
  }
}

/** Show, in `form`, the choice of a challenge to `player`: a game and its options; `send(body)`
 *  with the body of POST /api/challenges when sent (the form closes once it resolves). */
export function challengeForm(form, player, send, onError) {
  form.hidden = false;
  form.replaceChildren(el("h2", `Challenge ${player.name}`));
  const game = el("select");
  game.name = "game";
  game.setAttribute("aria-label", "Game");
  for (const g of GAMES) game.append(new Option(GAME_NAMES[g], g));
  const options = el("span", null, "row options");
  let read = optionControls(options, game.value, TABLE_OPTIONS);
  game.onchange = () => (read = optionControls(options, game.value, TABLE_OPTIONS));
  const submit = el("button", "Send the challenge", "primary");
  submit.type = "submit";
  const cancel = el("button", "Cancel");
  cancel.type = "button";
  cancel.onclick = () => (form.hidden = true);
  const row = el("div", null, "row");
  row.append(game, options, submit, cancel);
  form.append(row);
  form.onsubmit = async (e) => {
    e.preventDefault();
    try {
      await send({ to: player.id, game: game.value, ...read() });
      form.hidden = true;
    } catch (err) {
      onError(err);
    }
  };
  game.focus();
}
