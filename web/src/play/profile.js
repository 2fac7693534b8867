// A player's name as a link to the player's profile page, /player/{display name}; a bot's
// and an empty seat's as plain text (they have no profile). Names are set as text, never HTML.
import { BOT_PREFIX } from "../net/protocol.js";

/** The profile page of the player named `name`. */
export function profileUrl(name) {
  return `/player/${encodeURIComponent(name)}`;
}

/** `text` (by default the player's name) linked to the profile of `player` ({id, name} or
 *  null), or a plain span for a bot or nobody. */
export function nameElement(player, text = player?.name ?? "") {
  const human = player && !player.id.startsWith(BOT_PREFIX);
  const element = document.createElement(human ? "a" : "span");
  element.textContent = text;
  if (human) {
    element.href = profileUrl(player.name);
    element.className = "profile";
  }
  return element;
}
