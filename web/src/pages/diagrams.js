// /diagrams: the engine's curves, recomputed by the server whenever a slider moves. The
// sliders' ranges and defaults come from the server (GET /diagrams/inputs), which refuses
// anything outside them; the motion curve is sampled here from the shot's trajectory segments.
// The families of whole shots and the real shots are simulated by the server's background
// worker, so their sliders ask on release, and the page loads them one after another.
import uPlot from "uplot";
import { drawRebounds, drawThrows } from "../diagrams/families.js";
import { realShots } from "../diagrams/realshots.js";
import { spinAt, velocityAt } from "../lib/trajectory.js";

const $ = (id) => document.getElementById(id);
const COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf"];
const SAMPLES = 300;

function width(el) {
  return Math.max(280, el.clientWidth - 8);
}

/** Sliders for `spec`; onChange(values) on every move ("input") or on release ("change"). */
function sliders(box, spec, onChange, event = "input") {
  const values = {};
  for (const [key, s] of Object.entries(spec)) {
    values[key] = s.default;
    const label = document.createElement("label");
    const input = document.createElement("input");
    Object.assign(input, { type: "range", min: s.min, max: s.max, step: (s.max - s.min) / 200, value: s.default, name: key });
    const out = document.createElement("output");
    out.textContent = String(Number(s.default.toPrecision(3)));
    input.addEventListener(event, () => {
      values[key] = Number(input.value);
      out.textContent = String(Number(values[key].toPrecision(3)));
      onChange(values);
    });
    label.append(document.createTextNode(s.label), out, document.createElement("br"), input);
    box.append(label);
  }
  return values;
}

/** Ask for a curve with these values; the latest answer wins, earlier ones are dropped. */
function fetcher(curve, draw) {
  let asked = 0;
  return async (values) => {
    const mine = ++asked;
    const query = new URLSearchParams(Object.entries(values).map(([k, v]) => [k, String(v)]));
    const response = await fetch(`/diagrams/${curve}?${query}`);
    const data = await response.json();
    if (mine !== asked) return;
    if (!response.ok) {
      $("diagram-error").textContent = data.reason ?? data.error ?? "refused";
      return;
    }
    $("diagram-error").textContent = "";
    draw(data);
  };
}

/** One uPlot chart that is created on first data and updated in place afterwards. */
function chart(el, options) {
  let plot = null;
  return (data) => {
    if (!plot) plot = new uPlot({ width: width(el), height: 300, ...options }, data, el);
    else plot.setData(data);
  };
}

function familiesDiagram(curve, spec, draw) {
  const update = fetcher(curve, (d) => draw($(`${curve}-families`), d));
  return update(sliders($(`${curve}-sliders`), spec, update, "change"));
}

function reboundSideDiagram(spec) {
  const draw = chart($("rebound_side-chart"), {
    scales: { x: { time: false } },
    axes: [{ label: "side spin (v/R; check < 0 < running)" }, { label: "angle from the normal (degrees)" }],
    series: [
      { label: "side" },
      { label: "off the cushion", stroke: COLOURS[0], width: 2 },
      { label: "once rolling", stroke: COLOURS[1], width: 2 },
    ],
  });
  const update = fetcher("rebound_side", (d) => draw([d.side, d.rebound_deg, d.settled_deg]));
  return update(sliders($("rebound_side-sliders"), spec, update, "change"));
}

function mathavanDiagram(spec) {
  const series = () => [{ label: "incidence" }, ...[-1, 0, 1, 2].map((k, i) => ({ label: `k = ${k}`, stroke: COLOURS[i], width: 2 }))];
  const speeds = chart($("mathavan-speed-chart"), {
    scales: { x: { time: false } },
    axes: [{ label: "incidence from the normal (degrees)" }, { label: "rebound speed (m/s)" }],
    series: series(),
  });
  const angles = chart($("mathavan-angle-chart"), {
    scales: { x: { time: false } },
    axes: [{ label: "incidence from the normal (degrees)" }, { label: "rebound angle (degrees)" }],
    series: series(),
  });
  const update = fetcher("mathavan", (d) => {
    speeds([d.incidence_deg, ...d.curves.map((c) => c.speed)]);
    angles([d.incidence_deg, ...d.curves.map((c) => c.rebound_deg)]);
  });
  update(sliders($("mathavan-sliders"), spec, update));
}

function throwDiagram(spec) {
  const draw = chart($("throw-chart"), {
    scales: { x: { time: false } },
    axes: [{ label: "cut angle (degrees)" }, { label: "throw (degrees)" }],
    series: [{ label: "cut" }, { label: "stun", stroke: COLOURS[0], width: 2 }, { label: "rolling", stroke: COLOURS[1], width: 2 }],
  });
  const update = fetcher("throw", (d) => draw([d.cut_deg, ...d.curves.map((c) => c.throw_deg)]));
  update(sliders($("throw-sliders"), spec, update));
}

function cushionDiagram(spec) {
  const spins = ["stun", "roll", "roll+side", "roll-side"];
  // A fresh list per chart: uPlot keeps its own state in each series object.
  const series = () => [
    { label: "incidence" },
    ...["mathavan", "han"].flatMap((model) =>
      spins.map((spin, i) => ({ label: `${model} ${spin}`, stroke: COLOURS[i], width: 2, dash: model === "han" ? [6, 4] : undefined })),
    ),
  ];
  const angles = chart($("cushion-chart"), {
    scales: { x: { time: false } },
    axes: [{ label: "incidence from the normal (degrees)" }, { label: "rebound angle (degrees)" }],
    series: series(),
  });
  const speeds = chart($("cushion-speed-chart"), {
    scales: { x: { time: false } },
    axes: [{ label: "incidence from the normal (degrees)" }, { label: "rebound speed / incoming speed" }],
    series: series(),
  });
  const update = fetcher("cushion", (d) => {
    angles([d.incidence_deg, ...d.curves.map((c) => c.rebound_deg)]);
    speeds([d.incidence_deg, ...d.curves.map((c) => c.speed_ratio)]);
  });
  update(sliders($("cushion-sliders"), spec, update));
}

function motionDiagram(spec) {
  const draw = chart($("motion-chart"), {
    scales: { x: { time: false }, ms: {}, rad: {} },
    axes: [{ label: "time (s)" }, { label: "m/s", scale: "ms" }, { label: "side spin (rad/s)", scale: "rad", side: 1, grid: { show: false } }],
    series: [
      { label: "t" },
      { label: "speed |v| (m/s)", stroke: COLOURS[0], width: 2, scale: "ms" },
      { label: "top/back spin as surface speed -R w_x (m/s)", stroke: COLOURS[1], width: 2, scale: "ms" },
      { label: "side spin w_z (rad/s)", stroke: COLOURS[2], width: 2, scale: "rad" },
    ],
  });
  const update = fetcher("motion", (d) => {
    const end = d.duration * 1.05;
    const t = [];
    const speed = [];
    const roll = [];
    const side = [];
    for (let k = 0; k <= SAMPLES; k++) {
      const time = (end * k) / SAMPLES;
      const v = velocityAt(d.segments, time);
      const w = spinAt(d.segments, time);
      t.push(time);
      speed.push(Math.hypot(v[0], v[1]));
      roll.push(-w[0] * d.R);
      side.push(w[2]);
    }
    draw([t, speed, roll, side]);
  });
  update(sliders($("motion-sliders"), spec, update));
}

async function main() {
  const spec = await (await fetch("/diagrams/inputs")).json();
  throwDiagram(spec.throw);
  cushionDiagram(spec.cushion);
  mathavanDiagram(spec.mathavan);
  motionDiagram(spec.motion);
  await familiesDiagram("rebounds", spec.rebounds, drawRebounds);
  await reboundSideDiagram(spec.rebound_side);
  await familiesDiagram("throws", spec.throws, drawThrows);
  await realShots((message) => {
    $("diagram-error").textContent = message;
  });
}

main().catch((e) => {
  $("diagram-error").textContent = `Could not load the diagrams: ${e.message}`;
});
