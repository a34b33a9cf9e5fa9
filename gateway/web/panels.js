// Rendering of the state into the page: the joint table with its limit bands, the timing and
// connection facts, the joints' colours for the 3D view. Plain functions of the data.

const NEAR_LIMIT_DEG = 10;

/** Set `el`'s text only when it changes: an unchanged page must not be laid out and painted
 * again at the frame rate (browsers may draw in software, several pages on one machine). */
export function setText(el, text) {
  if (el && el.textContent !== text) el.textContent = text;
}

function setAttr(el, name, value) {
  if (el && el.getAttribute(name) !== value) el.setAttribute(name, value);
}

export function fmt(v, digits) {
  return typeof v === 'number' && Number.isFinite(v) ? v.toFixed(digits) : '-';
}

function pct(x) {
  return typeof x === 'number' ? `${(x * 100).toFixed(0)} %` : '-';
}

/** 'ok', 'near' (within 10 deg of a limit) or 'limit' (within the margin), by position. */
export function zone(pos, ax) {
  if (typeof pos !== 'number' || !ax) return 'unknown';
  const dist = Math.min(pos - ax.min_deg, ax.max_deg - pos);
  if (dist <= (ax.limit_margin_deg ?? 1)) return 'limit';
  if (dist <= NEAR_LIMIT_DEG) return 'near';
  return 'ok';
}

/** The joints' colour names for the 3D view. */
export function jointColours(status, model, errorAxis) {
  const d = status.detail || {};
  const pos = status.axis_states?.position || [];
  return [0, 1, 2, 3, 4, 5].map((i) => {
    const bad =
      (status.operating_mode === 'ERROR' && errorAxis === i + 1) ||
      d.drive_fault?.[i] === true ||
      d.drive_online?.[i] === false;
    if (bad) return 'error';
    if (d.calibrated && d.calibrated[i] === false) return 'uncalibrated';
    const z = zone(pos[i], model?.axes?.[i]);
    if (z === 'limit') return 'error';
    if (z === 'near') return 'near';
    return 'ok';
  });
}

/** Fill the static rows of `#joints` from the model (names, limits). */
export function fillModel(table, model) {
  for (const ax of model.axes || []) {
    const tr = table.querySelector(`tbody tr[data-axis="${ax.axis}"]`);
    if (!tr) continue;
    tr.querySelector('.name').textContent = ax.name;
    tr.querySelector('.limits').textContent = `${ax.min_deg}..${ax.max_deg}`;
  }
}

export function renderJoints(table, status, model) {
  const s = status.axis_states || {};
  const cal = status.detail?.calibrated || [];
  for (let i = 0; i < 6; i++) {
    const tr = table.querySelector(`tbody tr[data-axis="${i + 1}"]`);
    if (!tr) continue;
    const pos = s.position?.[i];
    setText(tr.querySelector('.pos'), fmt(pos, 3));
    setText(tr.querySelector('.vel'), fmt(s.velocity?.[i], 2));
    setText(tr.querySelector('.cur'), fmt(s.current?.[i], 2));
    const c = tr.querySelector('.cal');
    setText(c, cal[i] === true ? 'yes' : cal[i] === false ? 'no' : '-');
    setAttr(c, 'data-cal', c.textContent);
    const ax = model?.axes?.[i];
    const band = tr.querySelector('.band');
    const z = zone(pos, ax);
    setAttr(band, 'data-zone', z);
    setAttr(band, 'class', `band ${z}`);
    if (ax && typeof pos === 'number') {
      const f = Math.max(0, Math.min(1, (pos - ax.min_deg) / (ax.max_deg - ax.min_deg)));
      const mark = band.querySelector('.band-mark');
      const left = `${(f * 100).toFixed(1)}%`;
      if (mark.style.left !== left) mark.style.left = left;
      setAttr(band, 'title', `${pos.toFixed(1)} deg within ${ax.min_deg}..${ax.max_deg} deg`);
    }
  }
}

function dl(el, pairs) {
  const key = JSON.stringify(pairs);
  if (el.dataset.key === key) return;
  el.dataset.key = key;
  el.textContent = '';
  for (const [k, v, cls] of pairs) {
    const dt = document.createElement('dt');
    dt.textContent = k;
    const dd = document.createElement('dd');
    dd.textContent = v;
    if (cls) dd.className = cls;
    el.append(dt, dd);
  }
}

export function renderTiming(el, timing, bus, counters) {
  if (!timing) {
    dl(el, [['timing', 'not in the state']]);
    return;
  }
  const r = timing.recent || timing;
  const us = (v) => (typeof v === 'number' ? `${v.toFixed(0)} us` : '-');
  const pairs = [
    [`wake-up latency (last ${fmt(r.window_s, 0)} s)`,
      `p50 ${us(r.latency_p50_us)}, p99 ${us(r.latency_p99_us)}, p99.9 ${us(r.latency_p99_9_us)}, max ${us(r.latency_max_us)}`],
    ['work max / budget', `${us(timing.work_max_us)} / ${us(timing.work_budget_us)}`,
      timing.work_max_us > timing.work_budget_us ? 'bad' : ''],
    ['over budget', String(timing.over_budget ?? '-'), timing.over_budget > 0 ? 'bad' : ''],
    ['overruns', String(timing.overruns ?? '-'), timing.overruns > 0 ? 'bad' : ''],
    ['cycle', `${fmt((timing.period_s || 0) * 1000, 1)} ms${timing.realtime === false ? ', not real-time' : ', real-time'}`,
      timing.realtime === false ? 'warn' : ''],
  ];
  if (counters) {
    const lost = counters.bad_frames + counters.frames_dropped + counters.events_dropped + counters.bus_errors;
    pairs.push(['bus errors',
      `bad frames ${counters.bad_frames}, dropped ${counters.frames_dropped}, events dropped ${counters.events_dropped}, bus ${counters.bus_errors}`,
      lost > 0 ? 'bad' : '']);
  }
  if (bus) {
    pairs.push(['bus load (worst case)', `${pct(bus.worst_case_load)} of ${bus.bitrate / 1000} kbit/s, budget ${pct(bus.load_budget)}`,
      bus.worst_case_load > bus.load_budget ? 'bad' : '']);
  }
  dl(el, pairs);
}

export function renderConnections(el, detail, frameOwner) {
  const a = detail?.access || {};
  const c = detail?.control || {};
  const refused = a.refused || {};
  const pairs = [
    ['controls the arm', c.this_connection ? 'this page' : (frameOwner ?? c.owner ?? 'nobody')],
    ['this page', a.peer ?? '-'],
    ['motion allowed from here', a.motion_allowed_here === false ? 'no (read-only)' : a.motion_allowed_here ? 'yes' : '-'],
    ['motion networks', String(a.motion_networks ?? '-')],
    ['secret required', a.secret_required ? `yes (${a.authenticated ? 'authenticated' : 'not authenticated'})` : 'no'],
    ['refused since start', Object.keys(refused).length
      ? Object.entries(refused).map(([k, v]) => `${k} ${v}`).join(', ') : '-'],
  ];
  dl(el, pairs);
}

/** p-th percentile (0..100) of the numbers in `xs`. */
export function percentile(xs, p) {
  if (!xs.length) return NaN;
  const s = [...xs].sort((a, b) => a - b);
  const i = Math.min(s.length - 1, Math.max(0, Math.ceil((p / 100) * s.length) - 1));
  return s[i];
}

/** The gateway's clients (`/api/connections`) as list items; `self` is this page's peer. */
export function renderClients(el, list, self) {
  el.replaceChildren();
  const clients = list?.clients || [];
  if (!clients.length) {
    const li = document.createElement('li');
    li.className = 'muted';
    li.textContent = 'none';
    el.append(li);
  }
  for (const c of clients) {
    const li = document.createElement('li');
    li.dataset.clientId = String(c.client_id);
    const mine = self && c.channel === 'browser pendant' && c.peer === self;
    li.textContent = `${c.channel} ${c.peer}${mine ? ' (this page)' : ''}${c.controls_the_arm ? ': controls the arm' : ''}`;
    if (c.controls_the_arm) li.className = 'owner';
    el.append(li);
  }
  if (list && list.owner_client_id && !clients.some((c) => c.controls_the_arm)) {
    const li = document.createElement('li');
    li.className = 'owner';
    li.textContent = `shared-memory client ${list.owner_client_id.toString(16)}: controls the arm`;
    el.append(li);
  }
}
