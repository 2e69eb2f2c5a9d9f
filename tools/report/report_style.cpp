// tiltfield report: the page's style sheet (kept in C++ so a build without npm still has it).
#include "report_internal.hpp"

namespace tf::reporting {

std::string_view report_css() {
  return R"css(
:root { --ink: #1d232b; --muted: #5f6b7a; --line: #dfe3e8; --bg: #f3f5f8; --panel: #ffffff;
        --good: #1e8e3e; --bad: #d93025; --warn: #e37400; --accent: #1a73e8; }
* { box-sizing: border-box; }
body { margin: 0; background: var(--bg); color: var(--ink);
       font: 14px/1.45 system-ui, -apple-system, "Segoe UI", Roboto, "Helvetica Neue", Arial, sans-serif; }
header.top { display: flex; justify-content: space-between; align-items: center; gap: 24px; padding: 18px 28px;
             background: #17202b; color: #fff; }
header .kicker { text-transform: uppercase; letter-spacing: .12em; font-size: 11px; color: #9fb3c8; }
header h1 { margin: 2px 0 4px; font-size: 26px; font-weight: 650; }
header .sub { color: #c5d1dd; font-size: 13px; }
header .note { margin-top: 6px; color: #ffd27a; font-size: 13px; }
.status { padding: 10px 18px; border-radius: 8px; font-weight: 650; font-size: 16px; white-space: nowrap; }
.status.good { background: #1e8e3e; } .status.bad { background: #d93025; }
.cards { display: grid; grid-template-columns: repeat(auto-fit, minmax(150px, 1fr)); gap: 12px; padding: 16px 28px 4px; }
.card { background: var(--panel); border: 1px solid var(--line); border-radius: 10px; padding: 10px 14px;
        border-top: 4px solid #c3cbd5; }
.card.good { border-top-color: var(--good); } .card.bad { border-top-color: var(--bad); }
.card.warn { border-top-color: var(--warn); }
.card .label { color: var(--muted); font-size: 12px; text-transform: uppercase; letter-spacing: .05em; }
.card .value { font-size: 24px; font-weight: 650; font-variant-numeric: tabular-nums; }
.card .unit { font-size: 14px; font-weight: 400; color: var(--muted); }
.card .detail { color: var(--muted); font-size: 12px; }
.panel { background: var(--panel); border: 1px solid var(--line); border-radius: 10px; margin: 14px 28px; padding: 12px 18px 16px; }
.panel h2 { margin: 2px 0 10px; font-size: 17px; font-weight: 650; }
.stages svg { width: 100%; height: auto; }
.viewer-wrap { display: flex; gap: 16px; align-items: stretch; }
.viewer { position: relative; flex: 1 1 auto; min-width: 0; height: 600px; border-radius: 8px; overflow: hidden;
          background: linear-gradient(#fdfdfe, #e4e9ef); border: 1px solid var(--line); }
.viewer canvas { display: block; width: 100%; height: 100%; }
.viewer-msg { position: absolute; inset: 0; display: flex; align-items: center; justify-content: center;
              color: var(--muted); padding: 24px; text-align: center; }
.viewer-tip { position: absolute; pointer-events: none; background: rgba(23, 32, 43, .9); color: #fff; font-size: 12px;
              padding: 4px 8px; border-radius: 4px; display: none; white-space: nowrap; }
.viewer-side { flex: 0 0 270px; display: flex; flex-direction: column; gap: 14px; font-size: 13px; }
.layers label { display: flex; align-items: center; gap: 8px; padding: 3px 0; cursor: pointer; }
.layers .swatch { width: 14px; height: 14px; border-radius: 3px; flex: none; border: 1px solid rgba(0,0,0,.2); }
.layers .tri { color: var(--muted); font-size: 11px; margin-left: auto; }
.legend .title { font-weight: 600; margin-bottom: 4px; }
.legend .ramp { height: 14px; border-radius: 3px; border: 1px solid rgba(0,0,0,.2); }
.legend .ticks { display: flex; justify-content: space-between; color: var(--muted); font-size: 11px;
                 font-variant-numeric: tabular-nums; }
.hint { color: var(--muted); font-size: 12px; }
.plots { display: grid; grid-template-columns: repeat(auto-fit, minmax(520px, 1fr)); gap: 10px 18px; }
.plots figure { margin: 0; position: relative; }
.plots svg { width: 100%; height: auto; display: block; }
.plot-cursor { position: absolute; top: 0; pointer-events: none; background: rgba(23,32,43,.9); color: #fff;
               font-size: 11px; padding: 3px 6px; border-radius: 4px; display: none; white-space: nowrap; }
.caption { color: var(--muted); font-size: 12px; margin: 8px 0 0; }
.tables { display: grid; grid-template-columns: 3fr 2fr; gap: 24px; }
.tables h2 .count { display: inline-block; min-width: 24px; padding: 0 8px; border-radius: 12px; background: #e8ecf1;
                    font-size: 13px; text-align: center; }
.table-wrap { max-height: 420px; overflow: auto; border: 1px solid var(--line); border-radius: 6px; }
table { border-collapse: collapse; width: 100%; font-variant-numeric: tabular-nums; }
th, td { padding: 5px 10px; border-bottom: 1px solid #eef0f3; text-align: left; }
th { position: sticky; top: 0; background: #f7f8fa; font-weight: 600; font-size: 12px; color: var(--muted); }
td.num, th.num { text-align: right; }
tbody tr:hover { background: #f2f7ff; }
.rapid { color: var(--bad); font-weight: 600; }
.chips { display: flex; flex-wrap: wrap; gap: 6px; margin-bottom: 8px; }
.chip { background: #fdecea; color: #a50e0e; border-radius: 12px; padding: 2px 10px; font-size: 12px; }
.legend .chip, .legend-raw .chip { background: none; color: inherit; padding: 0 8px 0 0; font-size: 11px; }
.legend .chip i { display: inline-block; width: 10px; height: 10px; border-radius: 2px; margin-right: 4px;
  vertical-align: -1px; border: 1px solid rgba(0,0,0,.2); }
.legend-raw { margin-top: 4px; }
select.coloring { margin: 0 0 6px 22px; font: inherit; font-size: 12px; }
.none { color: var(--good); } .more { color: var(--muted); font-size: 12px; }
footer { color: var(--muted); font-size: 12px; padding: 4px 28px 24px; }
@media (max-width: 900px) { .viewer-wrap { flex-direction: column; } .viewer-side { flex-basis: auto; }
                            .tables { grid-template-columns: 1fr; } }
)css";
}

}  // namespace tf::reporting
