// tiltfield report: hover read-out for the static SVG plots. The C++ side writes each plot's frame
// (plot area in viewBox pixels and the data ranges) into a <metadata data-frame> element; the series are
// plain <path> elements, so the values under the pointer are read back from the drawn points.
const SVG = 'http://www.w3.org/2000/svg';

function parsePath(d) {
  const pts = [];
  const re = /[ML](-?[\d.]+),(-?[\d.]+)/g;
  let m;
  while ((m = re.exec(d))) pts.push([+m[1], +m[2]]);
  pts.sort((a, b) => a[0] - b[0]);
  return pts;
}

function nearest(pts, x) {
  let lo = 0, hi = pts.length - 1;
  while (hi - lo > 1) {
    const mid = (lo + hi) >> 1;
    if (pts[mid][0] < x) lo = mid; else hi = mid;
  }
  return Math.abs(pts[lo][0] - x) <= Math.abs(pts[hi][0] - x) ? pts[lo] : pts[hi];
}

const fmt = (v) => {
  const a = Math.abs(v);
  return a >= 1000 ? v.toFixed(0) : a >= 10 ? v.toFixed(1) : a >= 1 ? v.toFixed(2) : v.toFixed(3);
};

export function attachPlotCursors() {
  for (const svg of document.querySelectorAll('svg.plot')) {
    const meta = svg.querySelector('metadata.frame');
    if (!meta) continue;
    const [left, top, width, height, x0, x1, y0, y1] = meta.dataset.frame.split(',').map(Number);
    const xLabel = meta.dataset.xLabel || 'x';
    const series = [...svg.querySelectorAll('path.series')].map((p) => ({
      label: p.dataset.label, color: p.getAttribute('stroke'), pts: parsePath(p.getAttribute('d')),
    })).filter((s) => s.pts.length);
    const rule = document.createElementNS(SVG, 'line');
    rule.setAttribute('y1', top);
    rule.setAttribute('y2', top + height);
    rule.setAttribute('stroke', '#17202b');
    rule.setAttribute('stroke-width', '0.8');
    rule.setAttribute('visibility', 'hidden');
    rule.setAttribute('pointer-events', 'none');
    svg.appendChild(rule);
    const tip = document.createElement('div');
    tip.className = 'plot-cursor';
    svg.parentElement.appendChild(tip);
    svg.addEventListener('pointermove', (ev) => {
      const r = svg.getBoundingClientRect();
      const vb = svg.viewBox.baseVal;
      const px = ((ev.clientX - r.left) / r.width) * vb.width;
      if (px < left || px > left + width || !series.length) {
        rule.setAttribute('visibility', 'hidden');
        tip.style.display = 'none';
        return;
      }
      rule.setAttribute('x1', px);
      rule.setAttribute('x2', px);
      rule.setAttribute('visibility', 'visible');
      const x = x0 + ((px - left) / width) * (x1 - x0);
      const parts = [`${xLabel.replace(/\s*\(.*\)$/, '')} ${fmt(x)}`];
      for (const s of series) {
        const p = nearest(s.pts, px);
        parts.push(`${s.label} ${fmt(y0 + ((top + height - p[1]) / height) * (y1 - y0))}`);
      }
      tip.textContent = parts.join(' \u00b7 ');
      tip.style.display = 'block';
      const tx = ((px / vb.width) * r.width) + 10;
      tip.style.left = `${Math.min(tx, r.width - tip.offsetWidth - 4)}px`;
      tip.style.top = `${(top / vb.height) * r.height}px`;
    });
    svg.addEventListener('pointerleave', () => {
      rule.setAttribute('visibility', 'hidden');
      tip.style.display = 'none';
    });
  }
}
