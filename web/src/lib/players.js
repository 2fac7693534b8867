// Players' names as links to their profile page, /player/{name} (a name stands for the player
// who holds it now, or held it last: GET /api/players/named/{name}).
import { BOT_PREFIX } from "../net/protocol.js";

export function playerHref(name) {
  return `/player/${encodeURIComponent(name)}`;
}

/** A link to `player`'s profile ({id, name}); a bot, which has no profile, as plain text. */
export function playerLink(player) {
  if (player.id.startsWith(BOT_PREFIX)) return document.createTextNode(player.name);
  const a = document.createElement("a");
  a.href = playerHref(player.name);
  a.textContent = player.name;
  a.className = "player-link";
  return a;
}
