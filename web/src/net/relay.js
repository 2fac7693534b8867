// Reading a relay channel over WebSocket (ws+meta.nchan, so every frame carries its message id):
// reconnects by itself and resumes after the last id it saw, so nothing is missed; the relay
// says `gap` when it cannot replay everything, and the caller then fetches the full state.

const GAP_TYPE = "application/vnd.relay.gap+json";

export class Subscription {
  /** channel: its name; onMessage(json); onGap(); onState("open" | "closed"). */
  constructor(channel, { onMessage, onGap = () => {}, onState = () => {} }) {
    this.channel = channel;
    this.onMessage = onMessage;
    this.onGap = onGap;
    this.onState = onState;
    this.lastId = null;
    this.closed = false;
    this.retry = 500;
    this.connect();
  }

  url() {
    const scheme = location.protocol === "https:" ? "wss:" : "ws:";
    const resume = this.lastId ? `?last_event_id=${encodeURIComponent(this.lastId)}` : "";
    return `${scheme}//${location.host}/sub/${this.channel}${resume}`;
  }

  connect() {
    const ws = new WebSocket(this.url(), "ws+meta.nchan");
    this.ws = ws;
    ws.onopen = () => {
      this.retry = 500;
      this.onState("open");
    };
    ws.onmessage = (event) => this.frame(event.data);
    ws.onclose = () => {
      this.onState("closed");
      if (this.closed) return;
      setTimeout(() => this.connect(), this.retry);
      this.retry = Math.min(this.retry * 2, 8000);
    };
  }

  frame(data) {
    const split = data.indexOf("\n\n");
    const head = data.slice(0, split);
    const body = data.slice(split + 2);
    const fields = Object.fromEntries(head.split("\n").map((line) => [line.slice(0, line.indexOf(":")), line.slice(line.indexOf(":") + 1).trim()]));
    if (fields["content-type"] === GAP_TYPE) {
      this.onGap();
      return;
    }
    if (fields.id) this.lastId = fields.id;
    this.onMessage(JSON.parse(body));
  }

  close() {
    this.closed = true;
    this.ws.close();
  }
}
