// tiltfield report: the page's script entry (bundled by build.mjs into one IIFE that the binary embeds).
import { startViewer } from './viewer.js';
import { attachPlotCursors } from './plots.js';

function start() {
  attachPlotCursors();
  try {
    startViewer();
  } catch (e) {
    document.body.dataset.viewer = 'error';
    const host = document.getElementById('tf-viewer');
    if (host) host.textContent = `The 3-D view failed: ${e.message}`;
    throw e;
  }
}
if (document.readyState === 'loading') document.addEventListener('DOMContentLoaded', start);
else start();
