// tiltfield report: colour ramps shared by the 3-D view and its legends. A ramp is a list of
// [value, '#rrggbb'] stops in increasing value; colours between stops are interpolated linearly in sRGB.
import { Color } from 'three';

// Deviation from the design, in units of the layer's range: -1 the deepest over-cut shown (blue), 0 on
// the surface (green), +1 the most material left shown (red): the colours of the verifier's stock.ply.
export const DEVIATION_STOPS = [
  [-1, '#1a237e'], [-0.35, '#29b6f6'], [0, '#43a047'], [0.35, '#ffb74d'], [1, '#c62828'],
];

// The last block to cut, by rank among the blocks that cut (0 the first, 1 the last): a wide ramp so that
// neighbouring passes stay apart ("turbo"-like).
export const BLOCK_STOPS = [
  [0, '#30123b'], [0.2, '#4686fb'], [0.4, '#1ae4b6'], [0.6, '#a2fc3c'], [0.8, '#faba39'], [1, '#7a0403'],
];

// Tools: one colour each (Tableau 10), in the order of their numbers; raw stock grey.
export const TOOL_COLORS = ['#4e79a7', '#f28e2b', '#e15759', '#76b7b2', '#59a14f', '#edc948', '#b07aa1', '#ff9da7',
  '#9c755f', '#bab0ac'];
export const RAW_STOCK_COLOR = '#b8b2a6';

// Clearance to the check surfaces, mm: red at contact, amber at the safety distance, green beyond.
export function clearanceStops(safety, top) {
  const s = Math.max(safety, 1e-6);
  return [[0, '#d32f2f'], [s, '#ffb300'], [Math.max(top, 1.01 * s), '#2e7d32']];
}

const scratch = new Color();
export function colorAt(stops, v, out) {
  if (Number.isNaN(v)) return out.set('#9e9e9e');  // unknown
  if (!(v > stops[0][0])) return out.set(stops[0][1]);
  for (let i = 1; i < stops.length; ++i) {
    if (v <= stops[i][0]) {
      const [v0, c0] = stops[i - 1];
      const [v1, c1] = stops[i];
      return out.set(c0).lerp(scratch.set(c1), (v - v0) / (v1 - v0));
    }
  }
  return out.set(stops[stops.length - 1][1]);
}

// A CSS gradient of the stops across [lo, hi] (default: the stops' own range).
export function cssGradient(stops, lo = stops[0][0], hi = stops[stops.length - 1][0]) {
  const parts = stops.map(([v, c]) => `${c} ${(((v - lo) / (hi - lo)) * 100).toFixed(2)}%`);
  return `linear-gradient(to right, ${parts.join(', ')})`;
}
