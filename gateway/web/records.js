// The flight records: the list from /api/flight-records, and a chosen record plotted with uPlot
// (positions, velocities, currents per axis against the time before the trip; the trip is the
// last row of the file, marked with a vertical line and the check's name).

import uPlot from './vendor/uPlot.esm.js';

const AXIS_COLOURS = ['#1f77b4', '#d62728', '#2ca02c', '#9467bd', '#ff7f0e', '#17becf'];

export async function fetchRecords() {
  const r = await fetch('/api/flight-records', { cache: 'no-store' });
  if (!r.ok) throw new Error(`/api/flight-records: HTTP ${r.status}: ${(await r.text()).slice(0, 200)}`);
  return r.json();
}

/** The CSV as columns: {header: [...], cols: {name: [numbers or strings]}, rows}. */
export function parseCsv(text) {
  const lines = text.split(/\r?\n/).filter((l) => l.length > 0);
  if (lines.length < 2) throw new Error('the record has no rows');
  const header = lines[0].split(',');
  const cols = {};
  header.forEach((h) => { cols[h] = []; });
  for (let i = 1; i < lines.length; i++) {
    const f = lines[i].split(',');
    header.forEach((h, j) => {
      const n = Number(f[j]);
      cols[h].push(f[j] !== undefined && f[j] !== '' && !Number.isNaN(n) ? n : f[j]);
    });
  }
  return { header, cols, rows: lines.length - 1 };
}

function tripMarker(check) {
  return {
    hooks: {
      draw: [
        (u) => {
          const x = u.valToPos(0, 'x', true);
          const ctx = u.ctx;
          ctx.save();
          ctx.strokeStyle = '#d62828';
          ctx.lineWidth = 2 * (window.devicePixelRatio || 1);
          ctx.setLineDash([6, 4]);
          ctx.beginPath();
          ctx.moveTo(x, u.bbox.top);
          ctx.lineTo(x, u.bbox.top + u.bbox.height);
          ctx.stroke();
          ctx.setLineDash([]);
          ctx.fillStyle = '#d62828';
          ctx.font = `${12 * (window.devicePixelRatio || 1)}px sans-serif`;
          ctx.textAlign = 'right';
          ctx.fillText(`trip: ${check}`, x - 4, u.bbox.top + 14 * (window.devicePixelRatio || 1));
          ctx.restore();
        },
      ],
    },
  };
}

/** Plot `csv` (parsed) into `el` (emptied first); `check` names the trip. */
export function plotRecord(el, csv, check, names) {
  el.textContent = '';
  const t = csv.cols.t_s;
  if (!t) throw new Error('the record has no t_s column');
  const t0 = t[t.length - 1];
  const x = t.map((v) => v - t0);
  const last = csv.rows - 1;
  const caption = document.createElement('div');
  caption.className = 'plot-caption';
  caption.textContent =
    `${csv.rows} cycles, ${(-x[0]).toFixed(2)} s before the trip; the trip is the last row ` +
    `(cycle ${csv.cols.cycle[last]}, mode ${csv.cols.mode[last]}): ${check}`;
  el.appendChild(caption);
  // Three plots side by side (one above the other on a narrow screen).
  const width = Math.max(300, Math.floor((el.clientWidth - 24) / 3));
  const plots = [];
  const groups = [
    ['measured_deg_', 'position [deg]'],
    ['velocity_deg_s_', 'velocity [deg/s]'],
    ['current_a_', 'current [A]'],
  ];
  for (const [prefix, label] of groups) {
    const series = [{ label: 't [s]' }];
    const data = [x];
    for (let a = 1; a <= 6; a++) {
      const col = csv.cols[prefix + a];
      if (!col) continue;
      series.push({ label: `${a} ${names[a - 1] || ''}`.trim(), stroke: AXIS_COLOURS[a - 1], width: 1.5 });
      data.push(col);
    }
    const box = document.createElement('div');
    box.className = 'plot';
    el.appendChild(box);
    const opts = {
      title: label,
      width,
      height: 170,
      scales: { x: { time: false } },
      axes: [{ label: 's before the trip' }, { label, size: 60 }],
      series,
      legend: { show: true, live: false },
      plugins: [tripMarker(check)],
    };
    plots.push(new uPlot(opts, data, box));
  }
  return plots;
}

/** Fill `#records` from /api/flight-records; a click plots a record with the axis `names()`. */
export async function loadRecords(names) {
  const ul = document.querySelector('#records');
  let list;
  try {
    list = await fetchRecords();
  } catch (e) {
    ul.innerHTML = '';
    const li = document.createElement('li');
    li.className = 'none muted';
    li.textContent = `could not list the records: ${e.message}`;
    ul.appendChild(li);
    return;
  }
  const chosen = ul.querySelector('li.chosen')?.dataset.name;
  ul.textContent = '';
  if (!list.records.length) {
    const li = document.createElement('li');
    li.className = 'none muted';
    li.textContent = `no flight records yet (in ${list.dir})`;
    ul.appendChild(li);
  }
  for (const rec of list.records) {
    const li = document.createElement('li');
    li.dataset.name = rec.name;
    li.dataset.check = rec.check;
    if (rec.name === chosen) li.classList.add('chosen');
    const label = document.createElement('span');
    label.className = 'rec-label';
    label.textContent = `${stamp(rec.unix_ms)}  ${rec.check}  (${Math.round(rec.bytes / 1024)} KiB)`;
    label.title = `${rec.name}: click to plot`;
    const a = document.createElement('a');
    a.className = 'download';
    a.href = `/api/flight-records/${encodeURIComponent(rec.name)}`;
    a.setAttribute('download', rec.name);
    a.textContent = 'CSV';
    a.addEventListener('click', (e) => e.stopPropagation());
    li.append(label, ' ', a);
    li.addEventListener('click', () => showRecord(rec, li, names()));
    ul.appendChild(li);
  }
}

/** Local time as YYYY-MM-DD HH:MM:SS. */
function stamp(ms) {
  const d = new Date(ms);
  const p = (n) => String(n).padStart(2, '0');
  return `${d.getFullYear()}-${p(d.getMonth() + 1)}-${p(d.getDate())} ${p(d.getHours())}:${p(d.getMinutes())}:${p(d.getSeconds())}`;
}

async function showRecord(rec, li, names) {
  document.querySelectorAll('#records li.chosen').forEach((x) => x.classList.remove('chosen'));
  li.classList.add('chosen');
  const el = document.querySelector('#record-plot');
  el.textContent = `loading ${rec.name} ...`;
  try {
    const r = await fetch(`/api/flight-records/${encodeURIComponent(rec.name)}`, { cache: 'no-store' });
    if (!r.ok) throw new Error(`HTTP ${r.status}: ${(await r.text()).slice(0, 200)}`);
    const csv = parseCsv(await r.text());
    plotRecord(el, csv, rec.check, names);
    el.dataset.name = rec.name;
  } catch (e) {
    el.textContent = `could not plot ${rec.name}: ${e.message}`;
  }
}

