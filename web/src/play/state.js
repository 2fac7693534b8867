// The table as this client shows it: one object that only the server's messages change
// (docs/protocol.md). `apply` takes a whole TableView (the start, a resync, a `table`
// message), an `outcome` or a `presence` message; everything the page shows is drawn from
// here. It holds no rules: what the next shot may carry, what is legal to hit first and where
// the cue ball may go are the server's `next` (Constraints, with `next.shot` its ShotRules).

export class TableState {
  constructor() {
    this.view = null; // the TableView as the last message applied leaves it
    this.decided = null; // the last outcome with a referee's decision, or null
    this.grace = [null, null]; // per seat: when the opponent may claim (presence messages)
    this.replays = []; // {rack, id} of every rack seen to end with a replay, oldest first
  }

  /** Apply one server message: a TableView, or a channel message of kind `table`, `outcome`
   *  or `presence`. Versions are checked before (session.js): this applies what it is given. */
  apply(message) {
    if (message.kind === "outcome") this.applyOutcome(message);
    else if (message.kind === "presence") this.applyPresence(message);
    else this.applyView(message.kind === "table" ? message.view : message);
  }

  applyView(view) {
    this.view = structuredClone(view);
    const last = view.last_outcome;
    if (last?.decision) this.decided = last;
    if (last) this.noteReplay(last);
  }

  applyOutcome(message) {
    const fields = ["state", "next", "rack", "racks_won", "status", "winner", "version"];
    for (const key of fields) this.view[key] = message[key];
    this.view.last_outcome = message;
    if (message.decision) this.decided = message;
    this.noteReplay(message);
  }

  applyPresence(message) {
    if (!this.view) return;
    this.view.presence = message.presence;
    this.grace = message.grace_until ?? [null, null];
  }

  noteReplay(outcome) {
    if (!outcome.replay || this.replays.some((r) => r.id === outcome.replay)) return;
    // The outcome that ends a rack carries that rack's replay; `rack` is already the next one's
    // number when the match goes on.
    const rack = outcome.status === "playing" ? outcome.rack - 1 : outcome.rack;
    this.replays.push({ rack, id: outcome.replay });
  }

  /** The seat of player `me` ({id}), or null (a spectator, or nobody signed in). */
  seatOf(me) {
    if (!me || !this.view) return null;
    const seat = this.view.seats.findIndex((s) => s?.id === me.id);
    return seat < 0 ? null : seat;
  }

  /** What player `me` may do now: "shot", "choice" or null. */
  turnOf(me) {
    const v = this.view;
    const seat = this.seatOf(me);
    if (!v || v.status !== "playing" || !v.next || seat === null || v.next.seat !== seat) return null;
    return v.next.kinds.includes("choice") ? "choice" : "shot";
  }

  /** The next shot's ShotRules (docs/protocol.md), or null when no shot is to be played. */
  get shot() {
    return this.view?.next?.shot ?? null;
  }

  /** The seat whose player is gone from a running match, or -1. */
  goneSeat() {
    const v = this.view;
    if (!v || v.status !== "playing") return -1;
    return v.presence.findIndex((p, seat) => !p && v.seats[seat]);
  }

  /** May the opponent of the gone seat claim the win yet (its grace period is over)? */
  claimable(now = Date.now() / 1000) {
    const gone = this.goneSeat();
    const until = gone >= 0 ? this.grace[gone] : null;
    return until != null && until <= now;
  }
}
