// The families of shots the server simulates (GET /diagrams/rebounds, /diagrams/throws): one
// drawing per family, each shot's approach, tracks and measured angle.
import { BALL_COLOURS, SHOT_COLOURS, View, bounds } from "./draw.js";

const UNITS = { incidence_deg: (v) => `${v}°`, cut_deg: (v) => `cut ${v}°`, side: (v) => `side ${v}`, top: (v) => `top ${v}` };

function figure(box, family) {
  const fig = document.createElement("figure");
  fig.dataset.family = family.name;
  const caption = document.createElement("figcaption");
  caption.textContent = family.title;
  const canvas = document.createElement("canvas");
  canvas.width = 480;
  const legend = document.createElement("div");
  legend.className = "legend";
  fig.append(caption, canvas, legend);
  box.append(fig);
  return { canvas, legend };
}

function every(shot) {
  return [...shot.approach, ...Object.values(shot.tracks).flat(), ...(shot.centres ?? [])];
}

/** Draw one family: measure(shot) is the text after each shot's value in the legend. */
function drawFamily(box, family, data, measure) {
  const { canvas, legend } = figure(box, family);
  const points = family.shots.flatMap(every);
  const view = new View(canvas, bounds(points, 0.06));
  const [W, L] = data.table;
  view.rails(W, L);
  if (data.object_ball) view.ball(data.object_ball, data.R, BALL_COLOURS.object);
  family.shots.forEach((shot, i) => {
    const colour = SHOT_COLOURS[i % SHOT_COLOURS.length];
    view.line(shot.approach, colour, 1, [3, 3]);
    if (shot.centres) view.line(shot.centres, "#ffffff88", 1, [6, 4]);
    // The object ball's track bold, the cue ball's thin, both in the shot's colour.
    for (const [ball, track] of Object.entries(shot.tracks)) view.line(track, colour, ball === "object" ? 2.5 : 1.2);
    view.ball(shot.approach[1], data.R, BALL_COLOURS.cue);
    const item = document.createElement("span");
    item.style.color = colour;
    item.textContent = `${(UNITS[family.vary] ?? String)(shot.value)}: ${measure(shot)}  `;
    legend.append(item);
  });
}

const deg = (v) => (v === null ? "-" : `${v.toFixed(1)}°`);

export function drawRebounds(box, data) {
  box.replaceChildren();
  for (const family of data.families) {
    drawFamily(box, family, data, (s) => `off ${deg(s.rebound_deg)}, rolling ${deg(s.settled_deg)}`);
  }
}

export function drawThrows(box, data) {
  box.replaceChildren();
  for (const family of data.families) {
    drawFamily(box, family, data, (s) => `throw ${s.throw_deg.toFixed(2)}°`);
  }
}
