// gyrocomp report: builds the page from the JSON in #report-data with uPlot.
// Schema: include/gyrocomp/report.h. On success <body data-render-status="ok">, so a headless
// browser test can tell a drawn report from a broken one.
(function () {
  "use strict";
  const COLORS = ["#1f6feb", "#d1495b", "#2a9d8f", "#e9a03b", "#7b4fd6", "#5b6577", "#00798c", "#b35900"];
  const root = document.getElementById("report");

  function el(tag, attrs, text) {
    const e = document.createElement(tag);
    for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, v);
    if (text !== undefined && text !== null) e.textContent = String(text);
    return e;
  }
  function fmt(v) {
    if (typeof v !== "number") return v === null || v === undefined ? "n/a" : String(v);
    if (!isFinite(v)) return "n/a";
    if (v === 0) return "0";
    const a = Math.abs(v);
    return a >= 1e4 || a < 1e-3 ? v.toExponential(3) : v.toPrecision(4).replace(/\.?0+$/, "");
  }
  function width() { return Math.max(320, Math.min(root.clientWidth - 8, 1120)); }
  function section(title, note) {
    root.appendChild(el("h2", {}, title));
    if (note) root.appendChild(el("p", { class: "note" }, note));
  }
  function table(spec, parent) {
    const t = el("table");
    const head = el("tr");
    for (const c of spec.columns || []) head.appendChild(el("th", {}, c));
    t.appendChild(head);
    for (const row of spec.rows || []) {
      const tr = el("tr");
      for (const cell of row) tr.appendChild(el("td", {}, fmt(cell)));
      t.appendChild(tr);
    }
    (parent || root).appendChild(t);
    if (spec.note) (parent || root).appendChild(el("p", { class: "note" }, spec.note));
  }
  function chart(opts, data, parent) {
    const div = el("div", { class: "chart" });
    (parent || root).appendChild(div);
    return new uPlot(opts, data, div);
  }
  const logScale = { time: false, distr: 3, log: 10 };
  // Tick labels of a log axis: powers of ten only, in exponent form below 0.01 (uPlot's default
  // formatter rounds small values to "0").
  const logTicks = (u, splits) => splits.map(v => {
    if (v == null || v <= 0) return "";
    const e = Math.log10(v);
    if (Math.abs(e - Math.round(e)) > 1e-9) return "";
    return v >= 0.01 && v < 1e5 ? String(+v.toPrecision(1)) : "1e" + Math.round(e);
  });

  function drawTimeseries(ts) {
    section(ts.title || "Rate and temperature", ts.note || "Display only: each curve is a min/max envelope of the full-rate record.");
    const series = [{ label: ts.x_label || "time" }];
    const data = [ts.x];
    const axes = [{ label: ts.x_label || "time" }, { scale: "rate", label: "rate (deg/s)" }];
    let hasTemp = false;
    ts.series.forEach((s, i) => {
      const isTemp = s.axis === "temp";
      hasTemp = hasTemp || isTemp;
      series.push({ label: s.name, scale: isTemp ? "temp" : "rate", stroke: COLORS[i % COLORS.length], width: 1 });
      data.push(s.y);
    });
    if (hasTemp) axes.push({ scale: "temp", side: 1, label: "temperature (deg C)", grid: { show: false } });
    chart({ width: width(), height: 360, scales: { x: { time: false } }, series, axes }, data);
  }

  function drawModes(modes) {
    section("VMD modes, sample entropy and class",
      "Each mode's sample entropy decides its feature: drift (compensated), mixed (denoised by WFLP) or noise (discarded).");
    table({ columns: ["mode", "centre frequency (Hz)", "sample entropy", "class"],
            rows: modes.map(m => [m.index, m.center_frequency_hz, m.sample_entropy, m["class"]]) });
    const grid = el("div", { class: "grid" });
    root.appendChild(grid);
    modes.forEach((m, i) => {
      const box = el("div");
      box.appendChild(el("h3", { class: "cls-" + m["class"] },
        `mode ${m.index}: ${fmt(m.center_frequency_hz)} Hz, SE ${fmt(m.sample_entropy)}, ${m["class"]}`));
      grid.appendChild(box);
      if (m.x && m.y) {
        chart({ width: 360, height: 160, legend: { show: false }, scales: { x: { time: false } },
                series: [{}, { stroke: COLORS[i % COLORS.length], width: 1 }],
                axes: [{}, { size: 60 }] }, [m.x, m.y], box);
      }
    });
  }

  function drawAllan(curves) {
    section("Allan deviation",
      "Overlapping ADEV; shaded: confidence interval; dashed: fitted noise-term lines (ARW slope -1/2, bias instability floor, RRW slope +1/2).");
    const tables = [];
    const series = [{ label: "tau (s)" }];
    const bands = [];
    let col = 1;
    curves.forEach((c, i) => {
      const color = COLORS[i % COLORS.length];
      tables.push([c.tau_s, c.adev_dps, c.lo_dps || c.adev_dps, c.hi_dps || c.adev_dps]);
      series.push({ label: c.name, stroke: color, width: 2, spanGaps: true, points: { show: true, size: 4 } });
      series.push({ label: c.name + " low", stroke: color, width: 0, spanGaps: true, points: { show: false } });
      series.push({ label: c.name + " high", stroke: color, width: 0, spanGaps: true, points: { show: false } });
      bands.push({ series: [col + 2, col + 1], fill: color + "22" });
      col += 3;
      for (const line of c.lines || []) {
        tables.push([line.tau_s, line.adev_dps]);
        series.push({ label: c.name + ": " + line.name, stroke: color, dash: [6, 4], width: 1, spanGaps: true, points: { show: false } });
        col += 1;
      }
    });
    const data = uPlot.join(tables);
    chart({ width: width(), height: 420, bands,
            scales: { x: logScale, y: logScale },
            series, axes: [{ label: "tau (s)", values: logTicks }, { label: "ADEV (deg/s)", size: 70, values: logTicks }] }, data);
  }

  function drawDrift(d) {
    section("Drift against temperature", "Points: the drift feature (decimated); line: the fitted drift model; " +
            "dashed: its prediction band, where the drift of another run like this one is expected to lie.");
    const pts = d.temp_c.map((t, i) => [t, d.drift_dps[i]]).filter(p => p[0] !== null && p[1] !== null);
    pts.sort((a, b) => a[0] - b[0]);
    const tables = [[pts.map(p => p[0]), pts.map(p => p[1])]];
    const series = [{ label: "temperature (deg C)" },
      { label: "drift feature", stroke: COLORS[1], paths: () => null, points: { show: true, size: 3, fill: COLORS[1] } }];
    if (d.model_temp_c && d.model_dps) {
      const m = d.model_temp_c.map((t, i) => [t, d.model_dps[i]]).sort((a, b) => a[0] - b[0]);
      tables.push([m.map(p => p[0]), m.map(p => p[1])]);
      series.push({ label: "model", stroke: COLORS[0], width: 2, spanGaps: true, points: { show: false } });
      if (d.model_lo_dps && d.model_hi_dps) {  // the prediction band, dashed edges
        const pct = Math.round(100 * (d.band_level || 0.9));
        for (const [key, edge] of [["model_lo_dps", "lower"], ["model_hi_dps", "upper"]]) {
          const e = d.model_temp_c.map((t, i) => [t, d[key][i]]).sort((a, b) => a[0] - b[0]);
          tables.push([e.map(p => p[0]), e.map(p => p[1])]);
          series.push({ label: `${pct}% band (${edge})`, stroke: COLORS[0], width: 1, dash: [6, 4], spanGaps: true,
                        points: { show: false } });
        }
      }
    }
    chart({ width: width(), height: 360, scales: { x: { time: false } }, series,
            axes: [{ label: "temperature (deg C)" }, { label: "drift (deg/s)", size: 70 }] }, uPlot.join(tables));
  }

  // The columns of an xy chart (report.h, sections) on one sorted x: every points / line / band
  // entry has its own x, merged with duplicates kept (uPlot.join keeps one y per x of an entry,
  // and block means often share a temperature), null where an entry has no value.
  function xyData(spec) {
    const cols = [];
    for (const p of spec.points || []) cols.push([p.x, p.y]);
    for (const l of spec.lines || []) cols.push([l.x, l.y]);
    for (const b of spec.bands || []) { cols.push([b.x, b.lo]); cols.push([b.x, b.hi]); }
    const rows = [];
    cols.forEach((c, s) => c[0].forEach((x, i) => {
      if (x !== null && c[1][i] !== null) rows.push([x, s, c[1][i]]);
    }));
    rows.sort((a, b) => a[0] - b[0]);
    const data = [rows.map(r => r[0])];
    for (let s = 0; s < cols.length; ++s) data.push(new Array(rows.length).fill(null));
    rows.forEach((r, i) => { data[r[1] + 1][i] = r[2]; });
    return data;
  }

  // Points one colour per entry, lines solid, bands dashed edges with a fill between them.
  function drawXY(spec, parent, w) {
    const series = [{ label: spec.x_label || "x" }];
    const bands = [];
    (spec.points || []).forEach((p, i) => {
      const c = COLORS[i % COLORS.length];
      series.push({ label: p.name, stroke: c, paths: () => null, points: { show: true, size: 3, fill: c, stroke: c } });
    });
    for (const l of spec.lines || []) {
      series.push({ label: l.name, stroke: "#1d2330", width: 2, spanGaps: true, points: { show: false } });
    }
    for (const b of spec.bands || []) {
      const lo = series.length;
      for (const edge of ["lower", "upper"]) {
        series.push({ label: `${b.name} (${edge})`, stroke: "#5b6577", width: 1, dash: [6, 4], spanGaps: true,
                      points: { show: false } });
      }
      bands.push({ series: [lo + 1, lo], fill: "#5b657722" });
    }
    const box = el("div");
    parent.appendChild(box);
    if (spec.title) box.appendChild(el("h3", {}, spec.title));
    return chart({ width: w, height: 260, bands, legend: { live: false }, scales: { x: { time: false } }, series,
                   axes: [{ label: spec.x_label || "" }, { label: spec.y_label || "", size: 70 }] }, xyData(spec), box);
  }

  // One block per section: heading, note, table, its charts two abreast; data-charts = charts drawn.
  function drawSections(sections) {
    for (const s of sections) {
      const box = el("section", { class: "xy-section", "data-title": s.title || "" });
      root.appendChild(box);
      box.appendChild(el("h2", {}, s.title || ""));
      if (s.note) box.appendChild(el("p", { class: "note" }, s.note));
      if (s.table) table(s.table, box);
      const grid = el("div", { class: "grid2" });
      box.appendChild(grid);
      const w = Math.max(300, Math.floor((width() - 20) / 2));
      let drawn = 0;
      for (const c of s.charts || []) { drawXY(c, grid, w); ++drawn; }
      box.setAttribute("data-charts", String(drawn));
    }
  }

  function render() {
    const data = JSON.parse(document.getElementById("report-data").textContent);
    if (data.subtitle) root.appendChild(el("p", { class: "subtitle" }, data.subtitle));
    if (data.summary) { section(data.summary.title || "Before and after"); table(data.summary); }
    if (data.timeseries) drawTimeseries(data.timeseries);
    if (data.modes) drawModes(data.modes);
    if (data.allan) drawAllan(data.allan);
    if (data.drift) drawDrift(data.drift);
    if (data.sections) drawSections(data.sections);
    for (const t of data.tables || []) { section(t.title); table(t); }
    if (data.parameters) { section("Parameters", "Everything needed to repeat this run."); root.appendChild(el("pre", {}, JSON.stringify(data.parameters, null, 2))); }
    if (data.versions) { section("Software"); table({ columns: ["component", "version"], rows: Object.entries(data.versions) }); }
  }

  try {
    render();
    document.body.setAttribute("data-render-status", "ok");
  } catch (e) {
    document.body.setAttribute("data-render-status", "error");
    root.appendChild(el("p", { class: "error" }, "Report failed to render: " + e));
    console.error(e);
  }
})();
