// The maxk front panel: plain JavaScript, no build step, nothing from the network but
// this server. The server pushes the whole panel state as server-sent events
// (/api/stream); clicks go back as world settings in the @world words (/api/boards/N/world).
"use strict";

const token = new URLSearchParams(location.search).get("token");
const HISTORY_SECONDS = 10;
const history = {};  // "board/axis" -> [[time, position], ...]
const built = {};  // board number -> its elements

function api(path, body, method) {
  const url = path + (token ? (path.includes("?") ? "&" : "?") + "token=" + encodeURIComponent(token) : "");
  const init = body === undefined ? {method: method || "GET"} :
    {method: method || "POST", headers: {"Content-Type": "application/json"}, body: JSON.stringify(body)};
  return fetch(url, init).then(r => r.json().then(j => {
    if (!r.ok) document.getElementById("status").textContent = "refused: " + j.error;
    return j;
  }));
}

function el(tag, cls, text) {
  const e = document.createElement(tag);
  if (cls) e.className = cls;
  if (text !== undefined) e.textContent = text;
  return e;
}

function world(board, words) {
  return api("/api/boards/" + board + "/world", {words: words});
}

function buildBoard(b) {
  const box = el("section", "board");
  box.id = "board-" + b.number;
  box.appendChild(el("h2", "", "board " + b.number + ": " + b.model + " (" + b.kind + ")"));
  const time = el("div", "time");
  box.appendChild(time);
  const table = el("table", "axes");
  const head = el("tr");
  for (const h of ["axis", "position", "velocity", "-lim", "home", "+lim", "flags"]) head.appendChild(el("th", "", h));
  table.appendChild(head);
  const rows = {};
  for (const a of b.axes) {
    const tr = el("tr");
    tr.id = "axis-" + b.number + "-" + a.name;
    const cells = {name: el("td", "", a.name), position: el("td", "position"), velocity: el("td", "velocity")};
    tr.appendChild(cells.name); tr.appendChild(cells.position); tr.appendChild(cells.velocity);
    for (const side of ["minus", "home", "plus"]) {
      const td = el("td");
      const lamp = el("span", "lamp " + side, side === "home" ? "H" : (side === "plus" ? "+" : "-"));
      lamp.id = "lamp-" + b.number + "-" + a.name + "-" + side;
      lamp.title = "click: trip (stick active) or clear this switch in the world";
      lamp.addEventListener("click", () => {
        const stuck = lamp.dataset.fault === "active";
        world(b.number, a.name + " fault " + side + (stuck ? " none" : " active"));
      });
      td.appendChild(lamp);
      tr.appendChild(td);
      cells[side] = lamp;
    }
    cells.flags = el("td", "flags");
    tr.appendChild(cells.flags);
    table.appendChild(tr);
    rows[a.name] = cells;
  }
  box.appendChild(table);
  const chart = el("canvas", "chart");
  chart.width = 440; chart.height = 110;
  box.appendChild(chart);
  const inputs = el("div", "io");
  const outputs = el("div", "io");
  const analog = el("div", "io");
  box.appendChild(inputs); box.appendChild(outputs); box.appendChild(analog);
  const extras = el("div", "extras");
  box.appendChild(extras);
  const hosts = el("div", "hosts");
  box.appendChild(hosts);
  buildConsole(box, b.number);
  document.getElementById("boards").appendChild(box);
  built[b.number] = {box, time, rows, chart, inputs, outputs, analog, extras, hosts, bits: {}, xy: null};
  return built[b.number];
}

function bits(parent, store, key, levels, label, clickable, board) {
  if (!store[key]) {
    parent.appendChild(el("span", "", label + " "));
    store[key] = {};
    for (const n of Object.keys(levels)) {
      const bit = el("span", "bit" + (clickable ? " in" : ""), n);
      bit.id = key + "-" + board + "-" + n;
      if (clickable) bit.addEventListener("click", () =>
        world(board, "input " + n + (bit.classList.contains("on") ? " low" : " high")));
      parent.appendChild(bit);
      store[key][n] = bit;
    }
  }
  for (const [n, on] of Object.entries(levels)) {
    const bit = store[key][n];
    if (bit) bit.classList.toggle("on", on);
  }
}

function drawChart(canvas, series) {
  const g = canvas.getContext("2d");
  g.clearRect(0, 0, canvas.width, canvas.height);
  let lo = Infinity, hi = -Infinity, tmax = -Infinity;
  for (const pts of Object.values(series)) for (const [t, p] of pts) {
    lo = Math.min(lo, p); hi = Math.max(hi, p); tmax = Math.max(tmax, t);
  }
  if (!isFinite(lo)) return;
  if (hi - lo < 1) { hi += 1; lo -= 1; }
  const colors = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf"];
  let i = 0;
  for (const pts of Object.values(series)) {
    g.strokeStyle = colors[i++ % colors.length];
    g.beginPath();
    pts.forEach(([t, p], k) => {
      const x = canvas.width - (tmax - t) / HISTORY_SECONDS * canvas.width;
      const y = canvas.height - 4 - (p - lo) / (hi - lo) * (canvas.height - 8);
      if (k === 0) g.moveTo(x, y); else g.lineTo(x, y);
    });
    g.stroke();
  }
  g.fillStyle = "#555";
  g.fillText(hi.toFixed(0), 2, 10);
  g.fillText(lo.toFixed(0), 2, canvas.height - 2);
}

function drawExtras(view, b) {
  const x = b.extras;
  const box = view.extras;
  if (x.xy) {
    if (!view.xy) { view.xy = el("canvas", "xy"); view.xy.width = 220; view.xy.height = 220; box.appendChild(view.xy); view.xyInfo = el("div"); box.appendChild(view.xyInfo); }
    const [ax, ay] = x.xy;
    const px = history[b.number + "/" + ax] || [], py = history[b.number + "/" + ay] || [];
    const pts = px.map((p, k) => [p[1], (py[k] || [0, 0])[1]]);
    const all = pts.concat(x.pulse_points);
    const g = view.xy.getContext("2d");
    g.clearRect(0, 0, 220, 220);
    if (all.length) {
      let x0 = Math.min(...all.map(p => p[0])), x1 = Math.max(...all.map(p => p[0]));
      let y0 = Math.min(...all.map(p => p[1])), y1 = Math.max(...all.map(p => p[1]));
      const span = Math.max(x1 - x0, y1 - y0, 1);
      const sx = v => 10 + (v - x0) / span * 200, sy = v => 210 - (v - y0) / span * 200;
      g.strokeStyle = "#1f77b4"; g.beginPath();
      pts.forEach((p, k) => k ? g.lineTo(sx(p[0]), sy(p[1])) : g.moveTo(sx(p[0]), sy(p[1])));
      g.stroke();
      g.fillStyle = "#d62728";
      for (const p of x.pulse_points) g.fillRect(sx(p[0]) - 1.5, sy(p[1]) - 1.5, 3, 3);
    }
    view.xyInfo.textContent = "XY path (axes " + ax + ", " + ay + "), " + x.pulses + " pulses";
  }
  if (x.pwm) {
    if (!view.pwm) { view.pwm = el("div", "pwm"); box.appendChild(view.pwm); view.pwmChart = el("canvas"); view.pwmChart.width = 440; view.pwmChart.height = 60; box.appendChild(view.pwmChart); }
    view.pwm.textContent = "PWM mark: " + Object.entries(x.pwm).map(([a, d]) => "axis " + a + " " + (100 * d).toFixed(1) + "%").join(", ");
    for (const [a, d] of Object.entries(x.pwm)) push(b.number + "/pwm" + a, b.time, d);
    const series = {};
    for (const a of Object.keys(x.pwm)) series[a] = history[b.number + "/pwm" + a];
    drawChart(view.pwmChart, series);
  }
  if (x.buffer) {
    if (!view.buffer) { view.buffer = el("div", "buffer"); box.appendChild(view.buffer); }
    const f = x.buffer.count / x.buffer.depth;
    view.buffer.innerHTML = "";
    view.buffer.appendChild(el("span", "", "slot buffer " + x.buffer.count + "/" + x.buffer.depth + " "));
    const bar = el("span", "bar"); const fill = el("span"); fill.style.width = (100 * f) + "%";
    bar.appendChild(fill); view.buffer.appendChild(bar);
  }
}

function push(key, t, v) {
  const h = history[key] || (history[key] = []);
  if (h.length && t < h[h.length - 1][0]) h.length = 0;  // a reset clock starts afresh
  h.push([t, v]);
  while (h.length && h[0][0] < t - HISTORY_SECONDS) h.shift();
}

function update(state) {
  for (const b of state.boards) {
    const view = built[b.number] || buildBoard(b);
    view.time.textContent = "t = " + b.time.toFixed(3) + " s, tick " + b.tick + (b.speed === 0 ? " (paused)" : (b.speed !== 1 ? " (x" + b.speed + ")" : "")) + (b.trace ? ", tracing" : "");
    const series = {};
    for (const a of b.axes) {
      const cells = view.rows[a.name];
      if (!cells) continue;
      cells.position.textContent = a.position;
      cells.velocity.textContent = Math.round(a.velocity);
      for (const side of ["minus", "home", "plus"]) {
        const lamp = cells[side], s = a.lamps[side];
        lamp.classList.toggle("on", s.on);
        lamp.classList.toggle("stuck", !!s.fault);
        lamp.dataset.fault = s.fault || "";
      }
      const flags = a.flags.slice();
      if (a.done && !flags.includes("done")) flags.unshift("done");
      if (a.moving) flags.unshift("moving");
      const key = flags.join(" ");
      if (cells.flagsKey !== key) {  // the DOM touched only when something changed
        cells.flagsKey = key;
        cells.flags.innerHTML = "";
        for (const f of flags) cells.flags.appendChild(el("span", "flag" + (/err|slip|limit|overtravel/.test(f) ? " err" : ""), f));
      }
      push(b.number + "/" + a.name, b.time, a.position);
      if (a.moving || history[b.number + "/" + a.name].some(p => p[1] !== a.position)) series[a.name] = history[b.number + "/" + a.name];
    }
    drawChart(view.chart, series);
    if (Object.keys(b.inputs).length) bits(view.inputs, view.bits, "in", b.inputs, "inputs", true, b.number);
    if (Object.keys(b.outputs).length) bits(view.outputs, view.bits, "out", b.outputs, "outputs", false, b.number);
    if (Object.keys(b.analog).length) view.analog.textContent = "analog: " + Object.entries(b.analog).map(([c, v]) => c + " " + v.toFixed(3) + " V").join(", ");
    drawExtras(view, b);
    const hostsKey = JSON.stringify(b.hosts);
    if (view.hostsKey === hostsKey) continue;
    view.hostsKey = hostsKey;
    view.hosts.innerHTML = "";
    for (const h of b.hosts) {
      view.hosts.appendChild(el("div", "", h.transport + " " + h.peer));
      const pre = el("pre");
      pre.textContent = h.entries.map(e => e.time.toFixed(4) + (e.direction === "in" ? " <- " : " -> ") + JSON.stringify(e.text)).join("\n");
      view.hosts.appendChild(pre);
    }
  }
  const errors = document.getElementById("errors");
  errors.textContent = state.errors.map(e => e.level + " " + e.message).join("\n");
  if (state.boards.length) document.getElementById("clock").textContent = "t = " + state.boards[0].time.toFixed(2) + " s";
}

// ---- the console: the controller's own language, run by the server's console (the
// REPL's): this page only shows lines, keeps the history and asks for completions.
function buildConsole(box, number) {
  const wrap = el("div", "console");
  wrap.id = "console-" + number;
  const out = el("pre", "console-out");
  out.id = "console-out-" + number;
  const status = el("div", "console-status");
  status.id = "console-status-" + number;
  const row = el("div", "console-row");
  const prompt = el("span", "console-prompt", ">");
  const input = el("input", "console-in");
  input.id = "console-in-" + number;
  input.autocomplete = "off"; input.spellcheck = false;
  input.placeholder = "type a command (help, Tab completes)";
  const save = el("a", "console-save", "save as script");
  save.id = "console-save-" + number;
  save.href = "/api/boards/" + number + "/console/script" + (token ? "?token=" + encodeURIComponent(token) : "");
  save.download = "board" + number + ".maxk";
  const hint = el("div", "console-hint");
  hint.id = "console-hint-" + number;
  row.appendChild(prompt); row.appendChild(input); row.appendChild(save);
  wrap.appendChild(out); wrap.appendChild(row); wrap.appendChild(hint); wrap.appendChild(status);
  box.appendChild(wrap);
  const past = [];
  let at = 0;
  const show = (text, cls) => {
    const line = el("div", cls, text);
    out.appendChild(line);
    while (out.childNodes.length > 500) out.removeChild(out.firstChild);
    out.scrollTop = out.scrollHeight;
  };
  input.addEventListener("keydown", ev => {
    if (ev.key === "Enter") {
      const line = input.value;
      input.value = ""; hint.textContent = "";
      if (line.trim() && past[past.length - 1] !== line) past.push(line);
      if (past.length > 200) past.shift();
      at = past.length;
      show(prompt.textContent + " " + line, "console-typed");
      api("/api/boards/" + number + "/console", {line: line}).then(r => {
        if (r.error) { show("! " + r.error, "console-err"); return; }
        for (const t of r.lines) show(t, "console-reply");
        for (const t of r.errors) show(t, "console-err");
        prompt.textContent = r.prompt.trim();
        status.textContent = r.status;
        wrap.dataset.lines = (+wrap.dataset.lines || 0) + 1;
      });
    } else if (ev.key === "ArrowUp" || ev.key === "ArrowDown") {
      ev.preventDefault();
      at = Math.max(0, Math.min(past.length, at + (ev.key === "ArrowUp" ? -1 : 1)));
      input.value = past[at] || "";
    } else if (ev.key === "Tab") {
      ev.preventDefault();
      const m = /[A-Za-z#?_]*$/.exec(input.value.slice(0, input.selectionStart));
      const word = m ? m[0] : "";
      if (!word) return;
      api("/api/boards/" + number + "/console/words?prefix=" + encodeURIComponent(word)).then(r => {
        const found = r.words || [];
        hint.textContent = found.map(w => w.word + "  " + w.summary).join("\n") + (r.more ? "\n(" + r.more + " more)" : "");
        if (found.length === 1) {
          const cut = input.selectionStart - word.length;
          input.value = input.value.slice(0, cut) + found[0].word + input.value.slice(input.selectionStart);
        }
      });
    }
  });
}

function connect() {
  const source = new EventSource("/api/stream" + (token ? "?token=" + encodeURIComponent(token) : ""));
  source.onopen = () => { document.getElementById("status").textContent = "live"; };
  source.onmessage = ev => { update(JSON.parse(ev.data)); document.body.dataset.updates = (+document.body.dataset.updates || 0) + 1; };
  source.onerror = () => { document.getElementById("status").textContent = "reconnecting..."; };
}

document.getElementById("pause").addEventListener("click", () => api("/api/clock", {pause: true}));
document.getElementById("run").addEventListener("click", () => api("/api/clock", {run: true}));
document.getElementById("step").addEventListener("click", () => api("/api/clock", {step: 0.1}));
connect();
