// The shooter's aim shown to the opponent and spectators (POST /api/tables/{id}/aim, an `aim`
// message on the table channel): one aim on its way at a time, the next sent no sooner than
// 250 ms after the server answered the last, and the last aim always sent, so the watchers see
// the cue settle where the shooter left it. The server never plays it.

/** Least time (ms) from the server's answer to an aim to the next aim sent. The server takes
 *  one aim per 200 ms (rate_limited beyond): an aim reaches it after the previous one's answer
 *  left it, so counted from the answer, no delay on the way can bring two aims closer. */
const AIM_EVERY_MS = 250;
/** How long (ms) an aim may go unanswered before the next one may go anyway: a stalled link
 *  must not stop the watchers seeing the aim once it mends. */
const AIM_ANSWER_MS = 3000;

export class AimShare {
  /** send(body) posts one aim; failures (a turn just ended, a dropped link) are dropped. */
  constructor(send) {
    this.send = send;
    this.last = -Infinity;
    this.waiting = null; // the aim to send when the interval allows
    this.timer = null;
    this.sending = false; // an aim is on its way
    this.inflight = Promise.resolve(); // the last aim sent, until the server has answered
  }

  /** Share aim {heading, power, elevation, a, b} with the cue ball at `place` (or null). */
  offer(aim, place) {
    const round = (x) => Number(x.toFixed(3));
    this.waiting = { heading: round(aim.heading), power: round(aim.power), elevation: aim.elevation, a: round(aim.a), b: round(aim.b), place };
    if (!this.timer && !this.sending) this.schedule();
  }

  schedule() {
    const wait = Math.max(0, this.last + AIM_EVERY_MS - performance.now());
    this.timer = setTimeout(() => this.flush(), wait);
  }

  flush() {
    this.timer = null;
    if (!this.waiting) return;
    const body = this.waiting;
    this.waiting = null;
    this.sending = true;
    const deadline = new Promise((resolve) => setTimeout(resolve, AIM_ANSWER_MS));
    this.inflight = Promise.race([this.send(body).catch(() => {}), deadline])
      .finally(() => {
        this.sending = false;
        this.last = performance.now();
        if (this.waiting && !this.timer) this.schedule();
      });
  }

  /** Resolves once no aim is on its way: a shot sent after it cannot overtake it (the aim of
   *  a turn already played would be refused). */
  settled() {
    return this.inflight;
  }

  /** Forget an aim not yet sent (the shot was played, the turn passed). */
  cancel() {
    clearTimeout(this.timer);
    this.timer = null;
    this.waiting = null;
  }
}
