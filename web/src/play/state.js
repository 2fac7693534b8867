// The table as this client shows it: one object that only the server's messages change
// (docs/protocol.md). `apply` takes a whole TableView (the start, a resync, a `table`
// message), an `outcome` or a `presence` message; everything the page shows is drawn from
// here. It holds no rules: what the next shot may carry, what is legal to hit first and where
// the cue ball may go are the server's `next` (Constraints, with `next.shot` its ShotRules).
import { KIND } from "../net/protocol.js";

/** How a match ended off the table (TableView.ended): its last rack's replay is unfinished. */
const ENDED_OFF_TABLE = ["resigned", "claimed"];

export class TableState {
  constructor() {
    this.view = null; // the TableView as the last message applied leaves it
    this.grace = [null, null]; // per seat: when the opponent may claim (presence messages)
  }

  /** Apply one server message: a TableView, or a channel message of kind `table`, `outcome`
   *  or `presence`. Versions are checked before (session.js): this applies what it is given. */
  apply(message) {
    if (message.kind === KIND.OUTCOME) this.applyOutcome(message);
    else if (message.kind === KIND.PRESENCE) this.applyPresence(message);
    else this.applyView(message.kind === KIND.TABLE ? message.view : message);
  }

  /** A whole view replaces everything, its `last_outcome` too: null after a practice table's
   *  re-rack, retake or set-up position, whose new rack has no input played yet. */
  applyView(view) {
    this.view = structuredClone(view);
  }

  applyOutcome(message) {
    const fields = ["state", "next", "rack", "racks_won", "status", "winner", "version"];
    for (const key of fields) this.view[key] = message[key];
    this.view.last_outcome = message;
    // The outcome that ends a rack carries its replay, the table's next one in rack order.
    if (message.replay && !this.view.replays.includes(message.replay)) this.view.replays.push(message.replay);
    // A match an outcome ends was decided by its racks (the server's other endings, a
    // resignation or a claim, come as a whole view).
    if (message.status === "over") this.view.ended = "racks";
  }

  applyPresence(message) {
    if (!this.view) return;
    this.view.presence = message.presence;
    this.grace = message.grace_until ?? [null, null];
  }

  /** The table's replays as the server lists them (TableView.replays: rack 1 first, every
   *  finished rack, then the rack being played when the match ended off the table if a shot
   *  was played in it), each {rack, id, unfinished}. */
  get replays() {
    const v = this.view;
    if (!v) return [];
    const cut = v.status === "over" && ENDED_OFF_TABLE.includes(v.ended) ? v.rack : null;
    return v.replays.map((id, i) => ({ rack: i + 1, id, unfinished: i + 1 === cut }));
  }

  /** The last input played on the table as its outcome told it (a shot with the referee's
   *  decision, a choice, an input the engine refused), or null: what the status describes. */
  get last() {
    return this.view?.last_outcome ?? null;
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
