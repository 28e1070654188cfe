"""The monitor's page: one HTML document and one script, served from memory.

Kept as Python strings rather than package data files so the page ships in every kind of
install (a wheel carries modules, while data files need packaging configuration). The script
is plain browser JavaScript with no build step and no third-party library: a canvas for the
map (grid cells, or even-odd filled polygons with y up when the world says so, roadmap edges,
nest / food / goal marks), paths, jobs and agents, and a side panel for the clock, messages
per second (or n/a when the record has no send times) and the per-agent metrics. It applies
the events of :mod:`swarmex.viz.monitor.events` to one state object, and exposes
``window.monitorSnapshot()`` (a plain copy of that state) for tests.
"""

INDEX_HTML = r"""<!doctype html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>swarmex monitor</title>
<style>
  * { box-sizing: border-box; }
  html, body { margin: 0; height: 100%; font: 13px/1.4 system-ui, sans-serif; color: #222; }
  body { display: flex; flex-direction: column; background: #fafafa; }
  header { padding: 8px 12px; background: #20242b; color: #eee; display: flex; gap: 12px;
           align-items: center; }
  header .title { opacity: 0.8; }
  #png { margin-left: auto; font: inherit; padding: 1px 8px; cursor: pointer; }
  .badge { padding: 2px 8px; border-radius: 10px; background: #555; }
  .badge.live { background: #2e7d32; } .badge.ended { background: #1565c0; }
  .badge.disconnected { background: #b71c1c; }
  main { flex: 1; display: flex; min-height: 0; }
  #stage { flex: 1; position: relative; min-width: 0; }
  #map { position: absolute; inset: 0; width: 100%; height: 100%; }
  aside { width: 330px; padding: 10px 12px; overflow-y: auto; border-left: 1px solid #ddd;
          background: #fff; }
  .clock { font: 600 20px/1.2 ui-monospace, monospace; margin-bottom: 6px; }
  .kv { display: flex; justify-content: space-between; padding: 1px 0; }
  .kv b { font-family: ui-monospace, monospace; }
  table { width: 100%; border-collapse: collapse; margin-top: 10px; }
  th, td { text-align: right; padding: 2px 4px; border-bottom: 1px solid #eee; }
  th:first-child, td:first-child { text-align: left; }
  td { font-family: ui-monospace, monospace; }
  .swatch { display: inline-block; width: 10px; height: 10px; border-radius: 50%;
            margin-right: 5px; vertical-align: -1px; border: 1px solid #0006; }
  h3 { margin: 14px 0 4px; font-size: 13px; }
  #final.hidden { display: none; }
  .nojobs #jobs-row, .nojobs #agents td:nth-child(4), .nojobs #agents th:nth-child(4) {
    display: none; }
  .note { color: #666; font-size: 12px; }
  .note:empty { display: none; }
</style>
</head>
<body>
<header>
  <strong>swarmex monitor</strong>
  <span class="title" id="title">waiting for a mission…</span>
  <button id="png" title="Save the current view as a PNG">save PNG</button>
  <span class="badge" id="status">connecting</span>
</header>
<main>
  <div id="stage"><canvas id="map"></canvas></div>
  <aside>
    <div class="clock">t = <span id="t">0.0</span> <span id="unit">s</span></div>
    <div class="kv"><span>speed</span><b id="speed">–</b></div>
    <div class="kv"><span id="rate-label">messages / s (last 10 s of mission)</span>
      <b id="rate">0.0</b></div>
    <div class="kv"><span id="messages-label">messages</span><b id="messages">0</b></div>
    <div class="note" id="messages-note"></div>
    <div class="kv" id="jobs-row"><span>jobs</span><b id="jobs">0</b></div>
    <div class="kv"><span>events received</span><b id="events">0</b></div>
    <table id="agents">
      <thead><tr><th>agent</th><th>x, y</th><th>moves</th><th>jobs</th><th>msgs</th></tr></thead>
      <tbody></tbody>
    </table>
    <section id="final" class="hidden">
      <h3 id="result">final</h3>
      <div id="totals"></div>
    </section>
  </aside>
</main>
<script src="/monitor.js"></script>
</body>
</html>
"""

MONITOR_JS = r""""use strict";
(() => {
  const PALETTE = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                   "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"];
  const RATE_WINDOW = 10;  // mission seconds over which messages/s is averaged
  // a networked mission's status events: shown, but not counted as the mission's messages
  // (the record counts the agents' broadcasts only, as the simulator does)
  const STATUS_KINDS = new Set(["finish", "left", "join"]);

  function unpaint(x, y) {
    const i = state.jobCells.findIndex((c) => c[0] === x && c[1] === y);
    if (i >= 0) { state.jobCells.splice(i, 1); state.jobs -= 1; layersDirty = true; }
  }
  const state = {};
  let dirty = true;
  let layersDirty = true;
  let pendingJobs = [];
  let draws = 0;

  function reset() {
    Object.assign(state, {
      hello: null, world: null, agents: new Map(), order: [], t: 0, ended: false,
      end: null, messages: 0, jobs: 0, msgTimes: [], msgHead: 0, jobCells: [], bounds: null,
      weights: new Map(), known: null, knownCols: 0, knownImg: null,
      knownCells: { free: 0, occupied: 0, frontier: 0 }, goals: [],
    });
    layersDirty = true;
    pendingJobs = [];
  }
  reset();
  state.status = "connecting";
  state.events = 0;
  state.frames = 0;

  function color(id) {
    const i = Math.max(0, state.order.indexOf(id));
    const n = state.order.length;
    return n <= PALETTE.length ? PALETTE[i] : `hsl(${(i * 137.508) % 360}, 70%, 45%)`;
  }

  function agent(id) {
    let a = state.agents.get(id);
    if (!a) {
      a = { id, x: null, y: null, path: [], moves: 0, jobs: 0, sent: 0, vehicle: null,
            carrying: false, informed: false };
      state.agents.set(id, a);
      if (!state.order.includes(id)) state.order.push(id);
    }
    return a;
  }

  function grow(x, y) {
    const b = state.bounds;
    if (!b) { state.bounds = { x0: x, y0: y, x1: x, y1: y }; layersDirty = true; return; }
    if (x < b.x0 || y < b.y0 || x > b.x1 || y > b.y1) {
      b.x0 = Math.min(b.x0, x); b.y0 = Math.min(b.y0, y);
      b.x1 = Math.max(b.x1, x); b.y1 = Math.max(b.y1, y);
      if (!(state.world && state.world.width)) layersDirty = true;
    }
  }

  function apply(ev) {
    state.events += 1;
    if (typeof ev.t === "number" && ev.t > state.t) state.t = ev.t;
    switch (ev.type) {
      case "hello":
        reset();
        state.hello = ev;
        for (const id of ev.agents || []) agent(id);
        // a hybrid mission says what each agent flies ("simulated", "mavlink")
        for (const v of ev.vehicles || []) agent(v.id).vehicle = v.kind;
        break;
      case "world":
        state.world = ev;
        layersDirty = true;
        break;
      case "move": {
        const a = agent(ev.agent);
        if (a.x !== null) a.moves += 1;
        a.x = ev.x; a.y = ev.y;
        a.path.push([ev.x, ev.y]);
        grow(ev.x, ev.y);
        break;
      }
      case "job": {
        const a = agent(ev.agent);
        a.jobs += 1;
        state.jobs += 1;
        state.jobCells.push([ev.x, ev.y, ev.agent]);
        pendingJobs.push([ev.x, ev.y, ev.agent]);
        break;
      }
      case "message": {
        if (ev.kind === "join" && typeof ev.vehicle === "string") {
          agent(ev.agent).vehicle = ev.vehicle;  // a spare: what it flies
        }
        // a job abandoned (failed, or its agent gone) is not done any more: un-paint it
        if ((ev.kind === "undone" || ev.kind === "left") && typeof ev.x === "number") {
          unpaint(ev.x, ev.y);
        }
        if (STATUS_KINDS.has(ev.kind)) break;  // the protocol's, not the mission's messages
        agent(ev.agent).sent += 1;
        state.messages += 1;
        state.msgTimes.push(ev.t);
        break;
      }
      case "status": {
        const a = agent(ev.agent);
        a.carrying = !!ev.carrying; a.informed = !!ev.informed;
        break;
      }
      case "known":
        applyKnown(ev);
        break;
      case "weights":
        for (const [i, n] of ev.edges || []) state.weights.set(i, n);
        break;
      case "goals":
        state.goals = (ev.goals || []).filter((g) => Array.isArray(g));
        break;
      case "end":
        state.ended = true;
        state.end = ev;
        if (state.status === "live") setStatus("ended");
        break;
      default:
        break;  // clock and unknown types only move the clock
    }
  }

  // the exploration team's merged map: 0 unknown, 1 free, 2 occupied, 3 frontier (free)
  const KNOWN_RGBA = [[176, 190, 197, 255], [0, 0, 0, 0], [40, 40, 40, 255],
                      [255, 152, 0, 255]];

  function applyKnown(ev) {
    const cols = ev.cols;
    const rows = state.world && state.world.height ? state.world.height
      : (state.world && state.world.cells ? state.world.cells.length : 0);
    if (!cols || !rows) return;
    if (!state.known || state.knownCols !== cols) {
      state.known = new Uint8Array(cols * rows);
      state.knownCols = cols;
      state.knownImg = new ImageData(cols, rows);
      for (let k = 0; k < cols * rows; k++) paintKnown(k, 0);
    }
    const K = state.known;
    for (const k of ev.free || []) { K[k] = 1; paintKnown(k, 1); }
    for (const k of ev.occupied || []) { K[k] = 2; paintKnown(k, 2); }
    for (const k of ev.not_frontier || []) if (K[k] === 3) { K[k] = 1; paintKnown(k, 1); }
    for (const k of ev.frontier || []) if (K[k] === 1) { K[k] = 3; paintKnown(k, 3); }
    let free = 0, occupied = 0, frontier = 0;
    for (let k = 0; k < K.length; k++) {
      const v = K[k];
      if (v === 1) free++; else if (v === 2) occupied++; else if (v === 3) frontier++;
    }
    state.knownCells = { free: free + frontier, occupied, frontier };
  }

  function paintKnown(k, v) {
    const d = state.knownImg.data, c = KNOWN_RGBA[v], i = 4 * k;
    d[i] = c[0]; d[i + 1] = c[1]; d[i + 2] = c[2]; d[i + 3] = c[3];
  }

  function rate() {
    const lo = state.t - RATE_WINDOW;
    while (state.msgHead < state.msgTimes.length && state.msgTimes[state.msgHead] <= lo) {
      state.msgHead += 1;
    }
    const span = Math.min(RATE_WINDOW, state.t);
    return span > 0 ? (state.msgTimes.length - state.msgHead) / span : 0;
  }

  // ------------------------------------------------------------------ drawing
  const canvas = document.getElementById("map");
  const ctx = canvas.getContext("2d");
  let background = null;
  let jobLayer = null;
  let view = null;

  function extent() {
    const w = state.world;
    if (w && Array.isArray(w.bounds) && w.bounds.length === 4) {
      return { x0: w.bounds[0], y0: w.bounds[1], x1: w.bounds[2], y1: w.bounds[3] };
    }
    if (w && w.width && w.height) {
      return w.kind === "grid"
        ? { x0: -0.5, y0: -0.5, x1: w.width - 0.5, y1: w.height - 0.5 }
        : { x0: 0, y0: 0, x1: w.width, y1: w.height };
    }
    const b = state.bounds || { x0: 0, y0: 0, x1: 1, y1: 1 };
    return { x0: b.x0 - 1, y0: b.y0 - 1, x1: b.x1 + 1, y1: b.y1 + 1 };
  }

  function layout() {
    const dpr = window.devicePixelRatio || 1;
    const w = Math.max(1, Math.round(canvas.clientWidth * dpr));
    const h = Math.max(1, Math.round(canvas.clientHeight * dpr));
    canvas.width = w; canvas.height = h;
    const e = extent();
    const margin = 12 * dpr;
    const scale = Math.min((w - 2 * margin) / (e.x1 - e.x0), (h - 2 * margin) / (e.y1 - e.y0));
    const ox = (w - scale * (e.x1 - e.x0)) / 2 - scale * e.x0;
    const oy = (h - scale * (e.y1 - e.y0)) / 2 - scale * e.y0;
    // y_up worlds (polygon JSON files) put y = y0 at the bottom: mirror y inside the extent
    view = { w, h, scale, ox, oy, e, flip: !!(state.world && state.world.y_up) };
    background = makeBackground();
    jobLayer = document.createElement("canvas");
    jobLayer.width = w; jobLayer.height = h;
    pendingJobs = state.jobCells.slice();
    layersDirty = false;
  }

  const px = (x) => view.ox + view.scale * x;
  const py = (y) => view.oy + view.scale * (view.flip ? view.e.y0 + view.e.y1 - y : y);

  function makeBackground() {
    const bg = document.createElement("canvas");
    bg.width = view.w; bg.height = view.h;
    const g = bg.getContext("2d");
    g.fillStyle = "#eceff1";
    g.fillRect(0, 0, view.w, view.h);
    const e = view.e;
    const w = state.world;
    if (w && w.cells && w.cells.length) {
      const rows = w.cells.length, cols = w.cells[0].length;
      const img = new ImageData(cols, rows);
      for (let r = 0; r < rows; r++) {
        const line = w.cells[r];
        for (let c = 0; c < cols; c++) {
          const k = 4 * (r * cols + c);
          const v = line[c] === "." ? 255 : 40;
          img.data[k] = v; img.data[k + 1] = v; img.data[k + 2] = v; img.data[k + 3] = 255;
        }
      }
      const small = document.createElement("canvas");
      small.width = cols; small.height = rows;
      small.getContext("2d").putImageData(img, 0, 0);
      g.imageSmoothingEnabled = false;
      g.drawImage(small, px(-0.5), py(-0.5), cols * view.scale, rows * view.scale);
      if (view.scale >= 10) {
        g.strokeStyle = "#0000001a";
        g.lineWidth = 1;
        g.beginPath();
        for (let c = 0; c <= cols; c++) { g.moveTo(px(c - 0.5), py(-0.5));
                                          g.lineTo(px(c - 0.5), py(rows - 0.5)); }
        for (let r = 0; r <= rows; r++) { g.moveTo(px(-0.5), py(r - 0.5));
                                          g.lineTo(px(cols - 0.5), py(r - 0.5)); }
        g.stroke();
      }
    } else {
      g.fillStyle = "#fff";
      g.fillRect(px(e.x0), Math.min(py(e.y0), py(e.y1)), (e.x1 - e.x0) * view.scale,
                 (e.y1 - e.y0) * view.scale);
    }
    if (w) {
      drawPolygons(g, w.polygons);
      drawEdges(g, w.edges);
      drawMarks(g, w.marks, w.kind === "grid");
    }
    return bg;
  }

  // the blocked region: rings of the obstacles' union (exteriors and holes), even-odd filled
  function drawPolygons(g, rings) {
    if (!Array.isArray(rings) || !rings.length) return;
    g.fillStyle = "rgb(40, 40, 40)";
    g.beginPath();
    for (const ring of rings) {
      if (!Array.isArray(ring) || ring.length < 3) continue;
      g.moveTo(px(ring[0][0]), py(ring[0][1]));
      for (let i = 1; i < ring.length; i++) g.lineTo(px(ring[i][0]), py(ring[i][1]));
      g.closePath();
    }
    g.fill("evenodd");
  }

  // a roadmap: thin segments under the agents' paths
  function drawEdges(g, edges) {
    if (!Array.isArray(edges) || !edges.length) return;
    g.strokeStyle = "#90a4aeb0";
    g.lineWidth = Math.max(1, (window.devicePixelRatio || 1) * 0.8);
    g.beginPath();
    for (const [x1, y1, x2, y2] of edges) { g.moveTo(px(x1), py(y1)); g.lineTo(px(x2), py(y2)); }
    g.stroke();
  }

  const MARKS = { nest: ["#6d4c41", "N"], food: ["#2e7d32", "F"], goal: ["#c62828", "G"] };

  // fixed places (nest, food, goal): on their cell in a grid, a disc around the point otherwise
  function drawMarks(g, marks, grid) {
    if (!Array.isArray(marks)) return;
    const dpr = window.devicePixelRatio || 1;
    const r = Math.max(7 * dpr, grid ? view.scale * 0.5 : view.scale * 1.5);
    g.font = `600 ${Math.round(r * 1.1)}px system-ui, sans-serif`;
    g.textAlign = "center"; g.textBaseline = "middle";
    for (const m of marks) {
      const [fill, letter] = MARKS[m.kind] || ["#455a64", String(m.kind || "?")[0]];
      const x = px(m.x), y = py(m.y);
      g.globalAlpha = 0.35;
      g.fillStyle = fill;
      if (grid) g.fillRect(x - r, y - r, 2 * r, 2 * r);
      else { g.beginPath(); g.arc(x, y, r, 0, 2 * Math.PI); g.fill(); }
      g.globalAlpha = 1;
      g.strokeStyle = fill;
      g.lineWidth = Math.max(2, r * 0.18);
      if (grid) g.strokeRect(x - r, y - r, 2 * r, 2 * r);
      else { g.beginPath(); g.arc(x, y, r, 0, 2 * Math.PI); g.stroke(); }
      g.fillStyle = fill;
      g.fillText(letter, x, y);
    }
  }

  function drawJobs() {
    const g = jobLayer.getContext("2d");
    const s = view.scale;
    const grid = !state.world || state.world.kind === "grid";
    g.globalAlpha = 0.35;
    for (const [x, y, id] of pendingJobs) {
      g.fillStyle = color(id);
      if (grid) g.fillRect(px(x - 0.5), py(y - 0.5), s, s);
      else { g.beginPath(); g.arc(px(x), py(y), Math.max(3, s * 0.3), 0, 2 * Math.PI); g.fill(); }
    }
    pendingJobs = [];
  }

  function draw() {
    if (layersDirty || !view || canvas.width !== Math.round(canvas.clientWidth *
        (window.devicePixelRatio || 1))) layout();
    drawJobs();
    ctx.drawImage(background, 0, 0);
    ctx.drawImage(jobLayer, 0, 0);
    const s = view.scale;
    const edges = state.world && state.world.edges;
    if (edges && state.weights.size) {  // roadmap weights: travelled edges, by their count
      const dpr = window.devicePixelRatio || 1;
      for (const [i, n] of state.weights) {
        const e = edges[i];
        if (!e || n <= 0) continue;
        ctx.strokeStyle = n >= 3 ? "#0d47a1" : n === 2 ? "#1976d2" : "#64b5f6";
        ctx.lineWidth = dpr * Math.min(1 + n, 5);
        ctx.beginPath(); ctx.moveTo(px(e[0]), py(e[1])); ctx.lineTo(px(e[2]), py(e[3]));
        ctx.stroke();
      }
    }
    if (state.known) {  // the team's merged map over the truth: unknown veiled, frontier lit
      const small = document.createElement("canvas");
      small.width = state.knownCols; small.height = state.known.length / state.knownCols;
      small.getContext("2d").putImageData(state.knownImg, 0, 0);
      ctx.imageSmoothingEnabled = false;
      ctx.drawImage(small, px(-0.5), py(-0.5), small.width * s, small.height * s);
    }
    ctx.lineJoin = "round"; ctx.lineCap = "round";
    ctx.lineWidth = Math.max(1.5, s * 0.08);
    // agents sharing cells would hide each other's paths: shift each by a fraction of a cell
    const m = state.order.length;
    const step = m > 1 ? Math.min(0.5 / (m - 1), 0.15) : 0;
    state.order.forEach((id, k) => {
      const a = state.agents.get(id);
      if (a.path.length < 2) return;
      const off = (k - (m - 1) / 2) * step;
      ctx.strokeStyle = color(id);
      ctx.beginPath();
      ctx.moveTo(px(a.path[0][0] + off), py(a.path[0][1] + off));
      for (let i = 1; i < a.path.length; i++) {
        ctx.lineTo(px(a.path[i][0] + off), py(a.path[i][1] + off));
      }
      ctx.stroke();
    });
    const r = Math.max(4, s * 0.32);
    for (const [id, gx, gy] of state.goals) {  // exploration goals: a cross in the robot's colour
      const d = Math.max(4, s * 0.6);
      ctx.strokeStyle = color(id); ctx.lineWidth = Math.max(2, s * 0.15);
      ctx.beginPath();
      ctx.moveTo(px(gx) - d, py(gy) - d); ctx.lineTo(px(gx) + d, py(gy) + d);
      ctx.moveTo(px(gx) - d, py(gy) + d); ctx.lineTo(px(gx) + d, py(gy) - d);
      ctx.stroke();
    }
    ctx.font = `${Math.round(r * 1.1)}px system-ui, sans-serif`;
    ctx.textAlign = "center"; ctx.textBaseline = "middle";
    for (const id of state.order) {
      const a = state.agents.get(id);
      if (a.x === null) continue;
      ctx.fillStyle = color(id);
      ctx.strokeStyle = "#000";
      ctx.lineWidth = Math.max(1, r * 0.15);
      ctx.beginPath(); ctx.arc(px(a.x), py(a.y), r, 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
      if (a.informed) {  // foraging: knows where the food is
        ctx.strokeStyle = "#ffc107"; ctx.lineWidth = Math.max(2, r * 0.3);
        ctx.beginPath(); ctx.arc(px(a.x), py(a.y), r * 1.45, 0, 2 * Math.PI); ctx.stroke();
      }
      if (a.carrying) {  // foraging: carries a unit
        ctx.fillStyle = "#00c853";
        ctx.fillRect(px(a.x) - r * 0.5, py(a.y) - r * 0.5, r, r);
      }
      if (r >= 7) { ctx.fillStyle = "#fff"; ctx.fillText(String(id), px(a.x), py(a.y)); }
    }
    draws += 1;
  }

  // ------------------------------------------------------------------ panel
  const $ = (id) => document.getElementById(id);
  // numbers with sensible digits; nested totals (per kind, per reason) as "key value" lists;
  // long per-agent lists shortened: what a person reads, never "[object Object]"
  function fmt(v) {
    if (typeof v === "number") return Number.isInteger(v) ? v.toLocaleString("en") : v.toFixed(2);
    if (v === null || v === undefined) return "–";
    if (Array.isArray(v)) {
      const head = v.slice(0, 8).map(fmt).join(", ");
      return v.length > 8 ? `${head}, … (${v.length})` : head;
    }
    if (typeof v === "object") {
      const parts = Object.entries(v).map(([k, x]) => `${k.replace(/_/g, " ")} ${fmt(x)}`);
      return parts.length ? parts.join(" · ") : "none";
    }
    if (typeof v === "boolean") return v ? "yes" : "no";
    return String(v);
  }

  function setStatus(s) {
    state.status = s;
    const el = $("status");
    el.textContent = s;
    el.className = "badge " + s;
  }

  function panel() {
    const h = state.hello;
    if (h) {
      $("title").textContent = h.title || `${h.mission} · ${h.algorithm}`;
      const unit = h.time_unit || "s";
      $("unit").textContent = unit;
      $("rate-label").textContent = `messages / ${unit} (last ${RATE_WINDOW} ${unit}`
        + `${unit === "s" ? "" : "s"} of mission)`;
      $("speed").textContent = h.speed ? `×${fmt(h.speed)}` : (h.source || "live");
    }
    $("t").textContent = state.t.toFixed(1);
    const mode = messageMode();
    const e = state.end;
    if (mode === "events") {
      $("rate").textContent = rate().toFixed(2);
      $("messages").textContent = state.messages;
      $("messages-label").textContent = "messages";
      $("messages-note").textContent = "";
    } else {
      // no per-message times: a rate would be invented, so say so; totals come with the end
      $("rate").textContent = "n/a";
      $("messages-label").textContent = mode === "none" ? "messages" : "messages (total)";
      $("messages").textContent = mode === "none" ? "none"
        : (e && typeof e.messages === "number" ? e.messages : "n/a");
      $("messages-note").textContent = mode === "none"
        ? "this mission sends no messages"
        : "the record keeps message totals only, shown at the end";
    }
    $("jobs").textContent = state.jobs;
    // jobs mean something in traversal and foraging only
    const m = state.hello && state.hello.mission;
    document.body.classList.toggle("nojobs", m === "exploration" || m === "roadmap");
    $("events").textContent = state.events;
    const body = document.querySelector("#agents tbody");
    if (body.rows.length !== state.order.length) {
      body.innerHTML = "";
      for (const id of state.order) {
        const tr = body.insertRow();
        tr.innerHTML = `<td><span class="swatch" style="background:${color(id)}"></span>${id}`
          + "<small></small></td><td></td><td></td><td></td><td></td>";
      }
    }
    state.order.forEach((id, i) => {
      const a = state.agents.get(id);
      const cells = body.rows[i].cells;
      cells[0].querySelector("small").textContent = a.vehicle ? ` · ${a.vehicle}` : "";
      cells[1].textContent = a.x === null ? "–" : `${fmt(a.x)}, ${fmt(a.y)}`;
      cells[2].textContent = a.moves;
      cells[3].textContent = a.jobs;
      cells[4].textContent = mode === "events" ? a.sent : agentTotal(id);
    });
    const fin = $("final");
    if (state.ended && state.end) {
      fin.className = "";
      $("result").textContent = `${e.complete ? "complete" : "incomplete"} · makespan `
        + `${fmt(e.makespan)} ${e.time_unit || ""}`;
      const totals = $("totals");
      if (!totals.childElementCount) {
        for (const [k, v] of Object.entries(e.metrics || {})) {
          const row = document.createElement("div");
          row.className = "kv";
          row.innerHTML = `<span></span><b></b>`;
          row.children[0].textContent = k.replace(/_/g, " ");
          row.children[1].textContent = fmt(v);
          totals.appendChild(row);
        }
      }
      if (state.status === "live") setStatus("ended");
    } else {
      fin.className = "hidden";
      $("totals").innerHTML = "";
    }
  }

  // "events": every message is an event; "totals": only the end's totals; "none"
  function messageMode() {
    const m = state.hello && state.hello.messages;
    return m === "totals" || m === "none" ? m : "events";
  }

  function agentTotal(id) {
    const e = state.end;
    if (!e || messageMode() === "none") return "–";
    const a = (e.agents || []).find((x) => x.id === id);
    const v = a && a.metrics ? (a.metrics.messages_sent ?? a.metrics.messages) : undefined;
    return typeof v === "number" ? v : "–";
  }

  // ------------------------------------------------------------------ snapshots
  function pngName() {
    const m = (state.hello && state.hello.mission) || "mission";
    return `swarmex-${m}-t${state.t.toFixed(1)}.png`;
  }

  $("png").addEventListener("click", () => {
    draw();
    canvas.toBlob((blob) => {
      const a = document.createElement("a");
      a.href = URL.createObjectURL(blob);
      a.download = pngName();
      a.click();
      setTimeout(() => URL.revokeObjectURL(a.href), 1000);
    }, "image/png");
  });

  // `swarmex monitor --snapshot-every S DIR`: the server asks the page (GET /config) to send
  // the view every S wall seconds; it writes each PNG into DIR
  async function snapshots() {
    let every = null;
    try { every = (await (await fetch("/config")).json()).snapshot_every; } catch (e) { return; }
    if (!(every > 0)) return;
    let lastEnded = false;
    setInterval(() => {
      if (!state.hello || (lastEnded && state.ended)) return;
      lastEnded = state.ended;
      draw();
      canvas.toBlob((blob) => {
        fetch(`/snapshot?t=${state.t.toFixed(2)}`, { method: "POST", body: blob });
      }, "image/png");
    }, every * 1000);
  }
  snapshots();

  // ------------------------------------------------------------------ wiring
  function connect() {
    const scheme = location.protocol === "https:" ? "wss://" : "ws://";
    const ws = new WebSocket(scheme + location.host + "/ws");
    ws.onopen = () => setStatus("live");
    ws.onmessage = (m) => {
      const batch = JSON.parse(m.data);
      for (const ev of Array.isArray(batch) ? batch : [batch]) apply(ev);
      state.frames += 1;
      dirty = true;
    };
    ws.onclose = () => {
      setStatus(state.ended ? "ended" : "disconnected");
      setTimeout(connect, 1000);
    };
  }

  function frame() {
    if (dirty) { draw(); dirty = false; }
    requestAnimationFrame(frame);
  }
  window.addEventListener("resize", () => { layersDirty = true; dirty = true; });
  setInterval(() => { panel(); if (dirty && document.hidden) { draw(); dirty = false; } }, 200);
  requestAnimationFrame(frame);
  connect();

  window.monitorSnapshot = () => ({
    status: state.status,
    t: state.t,
    ended: state.ended,
    complete: state.end ? state.end.complete : null,
    makespan: state.end ? state.end.makespan : null,
    messages: state.messages,
    jobs: state.jobs,
    events: state.events,
    frames: state.frames,
    draws,
    mission: state.hello ? state.hello.mission : null,
    world: state.world ? { width: state.world.width, height: state.world.height,
                           rows: state.world.cells ? state.world.cells.length : 0 } : null,
    map: state.world ? {
      kind: state.world.kind,
      polygons: (state.world.polygons || []).length,
      edges: (state.world.edges || []).length,
      marks: (state.world.marks || []).map((m) => m.kind),
      yUp: !!state.world.y_up,
    } : null,
    messageMode: messageMode(),
    known: state.known ? { cols: state.knownCols, ...state.knownCells } : null,
    goals: state.goals.length,
    travelledEdges: [...state.weights.values()].filter((n) => n > 0).length,
    cellPixels: view ? view.scale : null,  // canvas pixels per map unit (a cell on grids)
    messageTotal: state.end && typeof state.end.messages === "number" ? state.end.messages : null,
    agents: state.order.map((id) => {
      const a = state.agents.get(id);
      return { id, x: a.x, y: a.y, moves: a.moves, jobs: a.jobs, sent: a.sent,
               path: a.path.length, vehicle: a.vehicle, carrying: a.carrying,
               informed: a.informed };
    }),
  });
})();
"""
