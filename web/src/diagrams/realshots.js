// The recorded real shots (docs/protocol.md, "Recorded real shots"): pick one, see its recorded
// and simulated tracks overlaid on the table with the strike and the RMSE, and refit it on the
// server within the server's bound. The server computes everything; this draws and asks.
import { get, post } from "../net/api.js";
import { BALL_COLOURS, View } from "./draw.js";

const $ = (id) => document.getElementById(id);

function strikeText(s) {
  const sign = (v) => (v >= 0 ? "+" : "") + v.toFixed(3);
  return `heading ${s.heading.toFixed(2)}°, cue speed ${s.speed.toFixed(3)} m/s, tip a ${sign(s.a)} b ${sign(s.b)} (R), struck at ${s.t0.toFixed(3)} s`;
}

function draw(canvas, table, fit) {
  const pad = 0.04;
  const view = new View(canvas, { x0: -pad, y0: -pad, x1: table.w + pad, y1: table.l + pad });
  view.rails(table.w, table.l);
  for (const [ball, rows] of Object.entries(fit.recorded)) {
    const colour = BALL_COLOURS[ball] ?? "#fff";
    view.line(rows.map((r) => [r[1], r[2]]), colour, 2.5);
    view.line(fit.simulated[ball].map((r) => [r[1], r[2]]), colour, 1.5, [7, 5]);
    view.ball([rows[0][1], rows[0][2]], table.R, colour);
  }
}

export async function realShots(report) {
  const [list, tables] = await Promise.all([get("/api/real-shots"), get("/web/tables")]);
  const table = tables.three_cushion;
  $("real-source").textContent = `${list.source} (median cue-ball RMSE ${list.median_rmse_cm.toFixed(2)} cm, engine version ${list.engine_version}). A refit runs at most ${list.max_simulations} simulations and ${list.max_seconds} s of the server's CPU.`;
  const select = $("real-shot");
  for (const s of list.shots) {
    select.append(new Option(`#${s.id}: ${s.duration.toFixed(1)} s, cue ${s.rmse_cm.toFixed(1)} cm`, String(s.id)));
  }
  let current = null;
  const show = (fit) => {
    current = fit;
    draw($("real-table"), table, fit);
    $("real-fit").textContent = `Shot #${fit.id} (cue ball ${fit.cue}): cue-ball RMSE ${fit.rmse_cm.toFixed(2)} cm, all balls ${fit.rmse_all_cm.toFixed(2)} cm. Strike: ${strikeText(fit.strike)}. ${fit.simulations} simulation${fit.simulations === 1 ? "" : "s"}, ${fit.seconds.toFixed(2)} s of CPU (${fit.stopped}).`;
  };
  const models = () => ({ cushion: $("real-cushion").value, ball_ball: $("real-ball-ball").value });
  const ask = async (work) => {
    $("real-refit").disabled = true;
    try {
      show(await work());
    } catch (e) {
      report(e.message);
    } finally {
      $("real-refit").disabled = false;
    }
  };
  const path = () => `/api/real-shots/${select.value}`;
  select.addEventListener("change", () => ask(() => get(path())));
  // Another model: the same strike simulated with it (one simulation); Refit then refines it.
  for (const id of ["real-cushion", "real-ball-ball"]) {
    $(id).addEventListener("change", () => ask(() => post(`${path()}/fit`, { strike: current?.strike, models: models(), simulations: 1 })));
  }
  $("real-refit").addEventListener("click", () =>
    ask(() => post(`${path()}/fit`, { strike: current?.strike, models: models(), simulations: list.max_simulations })),
  );
  await ask(() => get(path()));
}
