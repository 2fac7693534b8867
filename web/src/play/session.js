// One table as the client follows it: the full view from GET /api/tables/{id}, then the table
// channel's messages applied strictly in version order (docs/protocol.md, "Versions and
// resync"). A message one past ours is applied; an old one is ignored; a hole, a gap the
// relay reports, or a presence, chat or aim message (or a heartbeat's answer) at a newer
// version than ours fetches the full view again. Outcomes are handed on one at a time, each
// after the previous one's animation has finished.
import { get, post, shotId } from "../net/api.js";
import { HEARTBEAT_MS, KIND } from "../net/protocol.js";
import { Subscription } from "../net/relay.js";

export class TableSession {
  /**
   * handlers: onView(view) for a whole view (start, resync, `table` messages);
   * onOutcome(message) -> Promise resolved when it has been shown; onChat, onPresence, onAim
   * (the shooter's aim at the version shown);
   * onConnection("open" | "closed").
   */
  constructor(id, handlers) {
    this.id = id;
    this.h = handlers;
    this.version = -1;
    this.queue = Promise.resolve();
    this.heartbeat = null;
  }

  async start() {
    const view = await get(`/api/tables/${this.id}`);
    this.takeView(view);
    this.subscription = new Subscription(view.channel, {
      onMessage: (m) => this.receive(m),
      onGap: () => this.resync(),
      onState: (s) => {
        this.h.onConnection?.(s);
        // After a reconnect the relay replays what we missed; a resync also covers a server
        // that lost its buffer (restart without Redis).
        if (s === "open" && this.opened) this.resync();
        if (s === "open") this.opened = true;
      },
    });
    return view;
  }

  takeView(view) {
    this.version = view.version;
    this.enqueue(() => this.h.onView(view));
  }

  enqueue(step) {
    this.queue = this.queue.then(step).catch((e) => console.warn("table update failed", e));
  }

  receive(message) {
    if (message.protocol > 1) {
      location.reload();
      return;
    }
    const { kind } = message;
    if (kind === KIND.OUTCOME || kind === KIND.TABLE) return this.change(message);
    this.catchUp(message);
    if (kind === KIND.CHAT) this.h.onChat?.(message);
    else if (kind === KIND.PRESENCE) this.h.onPresence?.(message);
    else if (kind === KIND.AIM && message.version === this.version) this.h.onAim?.(message);
  }

  /** A message that carries the table's version without changing it (presence, chat, aim, a
   *  heartbeat's answer): one newer than ours means a change never reached us (a relay that
   *  lost its buffer in a restart says nothing of it), so fetch the table again. */
  catchUp(message) {
    if (message.version > this.version) this.resync();
  }

  /** An `outcome` or `table` message: applied in version order. */
  change(message) {
    if (message.version <= this.version) return;
    if (message.version > this.version + 1) {
      this.resync();
      return;
    }
    this.version = message.version;
    if (message.kind === KIND.TABLE) this.enqueue(() => this.h.onView(message.view));
    else this.enqueue(() => this.h.onOutcome(message));
  }

  /** Fetch the whole view and take it if it is newer than ours. One fetch at a time (aim
   *  messages come four a second, and each may ask for one): a request made meanwhile fetches
   *  once more after it, since its change may be newer than the answer on its way. */
  resync() {
    if (this.resyncing) {
      this.fetchAgain = true;
      return this.resyncing;
    }
    this.resyncing = (async () => {
      do {
        this.fetchAgain = false;
        try {
          const view = await get(`/api/tables/${this.id}`);
          if (view.version > this.version) this.takeView(view);
        } catch (e) {
          console.warn("resync failed", e);
        }
      } while (this.fetchAgain);
      this.resyncing = null;
    })();
    return this.resyncing;
  }

  /** Send an intent (a shot or a choice) for the version we show, under shot id `id`;
   *  resolves to the answer. */
  intent(input, id = shotId()) {
    return post(`/api/tables/${this.id}/intents`, { version: this.version, shot_id: id, input });
  }

  action(name, body = {}) {
    return post(`/api/tables/${this.id}/${name}`, body);
  }

  /** Keep telling the server we are here while seated (the opponent sees us otherwise gone). */
  beat(seated) {
    if (seated && !this.heartbeat) {
      // The answer is the table's presence, with the grace periods a reload would not know,
      // and the table's version: a newer one than ours is a change we missed.
      const send = () =>
        this.action("heartbeat")
          .then((m) => {
            this.catchUp(m);
            this.h.onPresence?.(m);
          })
          .catch(() => {});
      send();
      this.heartbeat = setInterval(send, HEARTBEAT_MS);
    } else if (!seated && this.heartbeat) {
      clearInterval(this.heartbeat);
      this.heartbeat = null;
    }
  }
}
