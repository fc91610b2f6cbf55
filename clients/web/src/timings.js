// The stage timings of one or two renders as a small horizontal bar chart in SVG, drawn by hand
// (a chart library would be larger than the rest of the page's own code). In: [{label, timings}],
// timings as {stage: milliseconds} in the server's stage order (Server-Timing or timings_ms). Out:
// an <svg> with one row per stage that took time in any render, a bar per render, and the totals.
const svgNs = "http://www.w3.org/2000/svg";
const colours = ["#3b6ea8", "#c0641d"];

function el(name, attrs = {}, text) {
  const node = document.createElementNS(svgNs, name);
  for (const [k, v] of Object.entries(attrs)) node.setAttribute(k, String(v));
  if (text !== undefined) node.textContent = text;
  return node;
}

export function formatMs(ms) {
  if (!Number.isFinite(ms)) return "?";
  if (ms >= 100) return `${ms.toFixed(0)} ms`;
  if (ms >= 10) return `${ms.toFixed(1)} ms`;
  return `${ms.toFixed(2)} ms`;
}

// Stages worth a row: every stage but the total, unless it took no time in any render.
export function chartStages(series) {
  const stages = [];
  for (const { timings } of series) {
    for (const stage of Object.keys(timings)) {
      const tookTime = series.some((s) => (s.timings[stage] || 0) > 0);
      if (stage !== "total" && tookTime && !stages.includes(stage)) stages.push(stage);
    }
  }
  return stages;
}

export function drawTimingChart(container, series) {
  const stages = chartStages(series);
  const labelWidth = 78;
  const valueWidth = 64;
  const width = 360;
  const barHeight = 9;
  const rowHeight = series.length * (barHeight + 2) + 6;
  const top = series.length > 1 ? 16 : 2;
  const height = top + stages.length * rowHeight + 4;
  const max = Math.max(1e-9, ...series.flatMap((s) => stages.map((st) => s.timings[st] || 0)));
  const svg = el("svg", { viewBox: `0 0 ${width} ${height}`, width: "100%", role: "img", class: "timing-chart" });
  const totals = series.map((s) => `${s.label}: ${formatMs(s.timings.total)}`).join(", ");
  svg.append(el("title", {}, `Stage timings (${totals})`));
  if (series.length > 1) {
    series.forEach((s, i) => {
      const x = labelWidth + i * 130;
      svg.append(el("rect", { x, y: 3, width: 10, height: 8, fill: colours[i] }));
      svg.append(el("text", { x: x + 14, y: 11, class: "legend" }, s.label));
    });
  }
  const barSpace = width - labelWidth - valueWidth;
  stages.forEach((stage, row) => {
    const y = top + row * rowHeight;
    svg.append(el("text", { x: labelWidth - 6, y: y + rowHeight / 2 + 3, "text-anchor": "end", class: "stage" }, stage));
    series.forEach((s, i) => {
      const ms = s.timings[stage] || 0;
      const by = y + 2 + i * (barHeight + 2);
      const w = Math.max(ms > 0 ? 1 : 0, (ms / max) * barSpace);
      const bar = el("rect", { x: labelWidth, y: by, width: w.toFixed(2), height: barHeight, fill: colours[i],
        class: "bar", "data-stage": stage, "data-series": s.label, "data-ms": ms });
      bar.append(el("title", {}, `${s.label} ${stage}: ${formatMs(ms)}`));
      svg.append(bar);
      svg.append(el("text", { x: labelWidth + w + 4, y: by + barHeight - 1, class: "value" }, formatMs(ms)));
    });
  });
  container.replaceChildren(svg);
  return svg;
}
