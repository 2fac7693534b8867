// Direct challenges in the lobby (docs/protocol.md, Challenges). The server announces every
// change of a challenge on both players' channels (`challenge`); the page also polls
// GET /api/challenges every QUICK_POLL_MS, which keeps its player present (a challenge lapses
// once either player has stopped polling) and is the truth about what is pending.
//
// A player channel replays its buffered messages to a new subscriber, so a `challenge` message
// is acted on only for a challenge this page has seen pending; any other one only makes the page
// ask the server again. A challenge received shows at once in the page and, when the player
// allowed it, as a browser notification.
import { post, get } from "../net/api.js";
import { KIND, QUICK_POLL_MS } from "../net/protocol.js";
import { GAME_NAMES } from "../lib/looks.js";
import { optionWords } from "../lib/options.js";
import { playerLink } from "../lib/players.js";

const SETTLED_WORDS = {
  declined: (c) => `${c.challenged.name} declined your challenge.`,
  cancelled: (c) => `${c.challenger.name} withdrew the challenge.`,
  lapsed: () => "A challenge lapsed: a player left the lobby.",
};

function el(tag, text, className) {
  const node = document.createElement(tag);
  if (text != null) node.textContent = text;
  if (className) node.className = className;
  return node;
}

/** "Snooker, 6 reds, race to 3". */
export function challengeWords(c) {
  const options = optionWords(c.choice.game, { ...c.choice, shot_clock: c.shot_clock });
  return [GAME_NAMES[c.choice.game] ?? c.choice.game, options].filter(Boolean).join(", ");
}

export class Challenges {
  /** box: where pending challenges show; me: the player; go(tableId): open a table;
   *  onError(e, near): show a refusal near element `near` (here, the box). */
  constructor(box, me, go, onError) {
    Object.assign(this, { box, me, go, onError });
    this.pending = new Map(); // id -> challenge, as last seen pending
    this.known = new Set(); // ids seen pending and not yet seen settled: settlements to act on
    this.notified = new Set();
    this.asking = null;
    this.refresh();
    setInterval(() => this.refresh(), QUICK_POLL_MS);
  }

  /** Ask the server what is pending (and stay present); at most one question at a time. */
  refresh() {
    this.asking ??= get("/api/challenges")
      .then((list) => this.show(list.challenges))
      .catch(() => {})
      .finally(() => (this.asking = null));
    return this.asking;
  }

  /** A message of the player's channel. */
  onMessage(m) {
    if (m.kind !== KIND.CHALLENGE) return;
    const c = m.challenge;
    if (!this.known.has(c.id)) {
      this.refresh();
      return;
    }
    if (c.status === "pending") return;
    this.known.delete(c.id);
    this.pending.delete(c.id);
    this.render();
    if (c.status === "accepted" && c.table) this.go(c.table);
    else this.notice(SETTLED_WORDS[c.status]?.(c) ?? "");
  }

  /** Send a challenge (the body as POST /api/challenges takes it). */
  async send(body) {
    const c = await post("/api/challenges", body);
    this.show([...this.pending.values(), c]);
  }

  show(challenges) {
    this.pending = new Map(challenges.map((c) => [c.id, c]));
    for (const c of challenges) {
      this.known.add(c.id);
      if (c.challenged.id === this.me.id && !this.notified.has(c.id)) {
        this.notified.add(c.id);
        notify(c);
      }
    }
    this.render();
  }

  async answer(c, verb) {
    try {
      const settled = await post(`/api/challenges/${c.id}/${verb}`);
      this.known.delete(c.id);
      this.pending.delete(c.id);
      this.render();
      if (settled.status === "accepted" && settled.table) this.go(settled.table);
    } catch (e) {
      this.onError(e, this.box);
      this.refresh();
    }
  }

  notice(text) {
    const line = this.box.querySelector(".challenge-notice") ?? el("p", null, "challenge-notice muted");
    line.textContent = text;
    this.box.append(line);
  }

  render() {
    this.box.querySelectorAll(".challenge").forEach((node) => node.remove());
    for (const c of this.pending.values()) {
      const received = c.challenged.id === this.me.id;
      const row = el("div", null, `challenge ${received ? "received" : "sent"}`);
      row.setAttribute("role", received ? "alert" : "status");
      const words = el("span");
      if (received) words.append(playerLink(c.challenger), ` challenges you: ${challengeWords(c)}. `);
      else words.append("You challenged ", playerLink(c.challenged), `: ${challengeWords(c)}. Waiting for an answer... `);
      row.append(words);
      const buttons = received
        ? [["Accept", "accept", "primary"], ["Decline", "decline", ""]]
        : [["Cancel", "cancel", ""]];
      for (const [text, verb, className] of buttons) {
        const button = el("button", text, className);
        button.type = "button";
        button.onclick = () => this.answer(c, verb);
        row.append(button);
      }
      this.box.prepend(row);
    }
    this.box.hidden = !this.box.children.length;
  }
}

/** A browser notification of a challenge received, if the player allowed them. */
function notify(c) {
  if (!("Notification" in window) || Notification.permission !== "granted") return;
  const note = new Notification(`${c.challenger.name} challenges you`, { body: challengeWords(c), tag: c.id });
  note.onclick = () => window.focus();
}
