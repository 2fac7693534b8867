// Who the player is: the stored identity if its token still holds, else a name asked for in a
// small form (POST /api/players). The header shows the name, as text.
import { currentPlayer, register } from "./api.js";

export function showWho(player) {
  const who = document.getElementById("who");
  if (who) who.textContent = player ? `Playing as ${player.name}` : "";
}

/** The player, asking for a name first if there is none; resolves once registered. */
export async function ensurePlayer() {
  const me = await currentPlayer();
  if (me) {
    showWho(me);
    return me;
  }
  return new Promise((resolve) => {
    const overlay = document.createElement("div");
    overlay.className = "overlay";
    overlay.innerHTML = `<form><h2>Your name</h2><div class="row"><input type="text" maxlength="24" required
      placeholder="Display name" aria-label="Display name" autocomplete="nickname"><button class="primary" type="submit">Play</button></div>
      <p class="error" role="alert"></p></form>`;
    const form = overlay.querySelector("form");
    const input = overlay.querySelector("input");
    form.addEventListener("submit", async (e) => {
      e.preventDefault();
      try {
        const player = await register(input.value.trim());
        overlay.remove();
        showWho(player);
        resolve(player);
      } catch (err) {
        overlay.querySelector(".error").textContent = err.message;
      }
    });
    document.body.append(overlay);
    input.focus();
  });
}
