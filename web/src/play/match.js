// The match around the table: join, resign (confirmed first), claim, cancel, the result panel
// once a match is over (who won and how, racks won, the rating change, the racks' replays) and
// the rematch, which takes both players to the new table as soon as the server has made it.
import { get } from "../net/api.js";
import { rackUnit, seatName } from "./words.js";

function button(label, onClick, className = "") {
  const b = Object.assign(document.createElement("button"), { type: "button", textContent: label, className });
  b.addEventListener("click", onClick);
  return b;
}

function el(tag, text, className = "") {
  return Object.assign(document.createElement(tag), { textContent: text, className });
}

/** How the match in view `v` (over, with a winner) was decided, in words: the server's
 *  `ended` (its racks, a resignation, or a claim after the loser left). */
export function resultWords(v) {
  const winner = seatName(v, v.winner);
  const loser = seatName(v, 1 - v.winner);
  const unit = rackUnit(v.game);
  const won = v.racks_won[v.winner];
  const how = {
    racks: `winning ${won} ${unit}${won === 1 ? "" : "s"} to ${v.racks_won[1 - v.winner]}`,
    resigned: `${loser} resigned`,
    claimed: `${loser} left and the win was claimed`,
  }[v.ended];
  return how ? `${winner} wins the match: ${how}.` : `${winner} wins the match.`;
}

export class MatchActions {
  /** page: {state, me, session, refused(error)}: the play page's table state and its player. */
  constructor(page) {
    this.page = page;
    this.confirming = false;
    this.ratingBefore = undefined; // the player's rating of this game when the page opened
  }

  async act(name) {
    try {
      await this.page.session.action(name);
    } catch (e) {
      this.page.refused(e);
    }
  }

  /** The buttons and panels for player seat `mine` (null: a spectator) in box. */
  show(box, mine) {
    const v = this.page.state.view;
    const list = [];
    if (mine !== null && v.status === "playing") list.push(...this.resignButtons(v.mode === "practice"));
    if (mine !== null && v.mode !== "practice") {
      if (this.page.state.claimable() && this.page.state.goneSeat() === 1 - mine) list.push(button("Claim the win", () => this.act("claim")));
      if (v.status === "open") list.push(button("Cancel", () => this.act("leave")));
    }
    if (v.status === "over") list.push(this.resultPanel(mine));
    else if (this.page.state.replays.length) list.push(this.replayList());
    box.replaceChildren(...list);
    if (v.rematch_table && mine !== null) location.assign(`/table/${v.rematch_table}`);
  }

  /** Resign, asked first; on a practice table the same ends the practice (its rack, finished
   *  or not, keeps its replay). */
  resignButtons(practice) {
    if (!this.confirming) return [button(practice ? "End practice" : "Resign", () => this.confirm(true))];
    return [
      el("span", practice ? "End this practice?" : "Resign the match?", "confirm"),
      button(practice ? "Yes, end it" : "Yes, resign", () => this.confirm(false, true), "danger"),
      button("Keep playing", () => this.confirm(false)),
    ];
  }

  confirm(asking, resign = false) {
    this.confirming = asking;
    if (resign) this.act("resign");
    this.page.render();
  }

  resultPanel(mine) {
    const v = this.page.state.view;
    const panel = el("section", "", "result");
    panel.id = "result";
    const unit = rackUnit(v.game);
    const title = v.winner != null ? resultWords(v) : v.mode === "practice" ? "Practice over." : "Match over.";
    panel.append(el("h2", title));
    if (v.mode !== "practice") panel.append(el("p", `${unit[0].toUpperCase()}${unit.slice(1)}s won: ${seatName(v, 0)} ${v.racks_won[0]}, ${seatName(v, 1)} ${v.racks_won[1]}.`));
    const rating = el("p", "", "rating");
    panel.append(rating);
    this.showRating(rating, mine);
    if (this.page.state.replays.length) panel.append(this.replayList());
    if (mine !== null && v.mode === "practice") {
      const again = el("a", "Practise again", "button primary");
      again.href = `/practice/${v.game}`;
      panel.append(again);
    }
    if (mine !== null && v.mode === "match") {
      const offered = v.rematch[1 - mine];
      if (offered && !v.rematch[mine]) panel.append(el("p", `${seatName(v, 1 - mine)} offers a rematch.`, "offer"));
      if (v.rematch[mine]) panel.append(el("p", `Rematch offered: waiting for ${seatName(v, 1 - mine)}.`));
      else panel.append(button(offered ? "Accept the rematch" : "Offer a rematch", () => this.act("rematch"), "primary"));
    }
    return panel;
  }

  /** The player's rating change in this game, once the server has rated the match. */
  showRating(box, mine) {
    const v = this.page.state.view;
    if (mine === null || v.mode !== "match" || this.ratingBefore == null) return;
    get(`/api/players/${this.page.me.id}/ratings`).then((r) => {
      const after = r.ratings[v.game]?.rating;
      if (after == null) return;
      const change = Math.round(after - this.ratingBefore);
      box.textContent = `Your rating: ${Math.round(after)} (${change >= 0 ? "+" : ""}${change}).`;
    });
  }

  /** Remember the player's rating before the match, for the change shown after it. */
  async noteRating(game) {
    if (!this.page.me) return;
    const r = await get(`/api/players/${this.page.me.id}/ratings`).catch(() => null);
    this.ratingBefore = r?.ratings?.[game]?.rating ?? 1500;
  }

  /** A link to the replay of every rack played (the server's list, so it survives a reload),
   *  the last one marked unfinished when the match ended before its rack did. */
  replayList() {
    const v = this.page.state.view;
    const box = el("div", "", "replays");
    box.id = "replays";
    box.append(el("span", "Replays: "));
    for (const { rack, id, unfinished } of this.page.state.replays) {
      const link = el("a", `${rackUnit(v.game)} ${rack}${unfinished ? " (unfinished)" : ""}`, "button");
      link.href = `/replay/${id}`;
      box.append(link);
    }
    return box;
  }
}
