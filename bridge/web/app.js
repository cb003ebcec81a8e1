// The bridge's live page: every device, its interfaces and, per service,
// the request and response states as swimlanes on a scrolling time axis.
// model.js keeps the devices and handshakes; this file fetches and draws.
//
// Data: the bridge's own MTConnect documents as JSON (format=json): /probe
// once (again after a restart or when a value names an unknown item), then
// /current plus a /sample of recent history, then /sample polled from
// nextSequence. Polling rather than the multipart `interval` stream: every
// answer is one complete document (no multipart parser, nothing buffered by
// a proxy, no fetch-stream support needed), a lost connection or a bridge
// restart is one failed request followed by a fresh start, and a poll that
// finds more than one page of news asks again at once.
//
// For tests and tools the body carries data attributes: data-state
// (loading, live, error), data-handshakes and data-fails (completed and
// failed handshakes seen), data-last-sequence (last observation read),
// data-last-complete-sequence and data-last-complete-lag-ms (the newest
// response COMPLETE and the time from its observation timestamp to its
// first drawing), data-ready-ms (navigation to first live drawing).
"use strict";

(() => {
  const POLL_MS = 200;      // pause between polls that found nothing more
  const RETRY_MS = 1000;    // pause after a failed request
  const HISTORY = 4000;     // observations read back at start
  const PAGE = 2000;        // observations per poll at most
  const FRAME_MS = 100;     // redraw period of the time axis
  const LANE_H = 20, GAP = 12;
  const SVG_NS = "http://www.w3.org/2000/svg";

  const page = {
    model: null,         // from the probe: devices, items by id
    instanceId: null,
    next: null,          // sequence of the next poll
    skewMs: 0,           // bridge clock minus ours, when large
    windowMs: 30000,
    paused: false,
    readyMs: null,
  };

  // ---------- small helpers ----------
  const $ = (id) => document.getElementById(id);
  const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));
  const { buildModel, observationsOf, pushState, apply, parseTime, list, counters } = MtcModel;

  function el(tag, className, text) {
    const e = document.createElement(tag);
    if (className) e.className = className;
    if (text !== undefined) e.textContent = text;
    return e;
  }

  function svg(tag, attrs) {
    const e = document.createElementNS(SVG_NS, tag);
    for (const [k, v] of Object.entries(attrs || {})) e.setAttribute(k, v);
    return e;
  }

  const words = (type) => type.toLowerCase().replace(/_/g, " ");
  const clock = (t) => new Date(t).toISOString().slice(11, 19);
  const now = () => Date.now() + page.skewMs;

  function formatMs(ms) {
    if (ms == null || !Number.isFinite(ms)) return "-";
    return ms < 1000 ? `${Math.round(ms)} ms` : `${(ms / 1000).toFixed(2)} s`;
  }

  class BridgeError extends Error {
    constructor(doc) {
      const errors = list(doc.MTConnectError.Errors, "Error");
      const first = errors[0] || {};
      super(`${first.errorCode || "ERROR"}: ${first.value || "the bridge refused the request"}`);
      this.code = first.errorCode;
    }
  }

  async function fetchJson(path) {
    const response = await fetch(path, { cache: "no-store", headers: { Accept: "application/json" } });
    let doc = null;
    try {
      doc = await response.json();
    } catch (e) {
      throw new Error(`${path}: HTTP ${response.status}, not JSON`);
    }
    if (doc && doc.MTConnectError) throw new BridgeError(doc);
    return doc;
  }

  // ---------- drawing ----------
  function serviceRow(service) {
    const row = el("div", "service");
    if (service.request) row.dataset.request = service.request.id;
    if (service.response) row.dataset.response = service.response.id;
    const label = el("div", "label");
    label.append(el("span", "name", words(service.type)));
    const roles = el("span", "roles");
    const side = (entry, role) => (entry ? `${role} · ${entry.device.name}` : `${role} · none paired`);
    roles.append(el("span", "", side(service.request, "request")),
                 el("span", "", side(service.response, "response")));
    label.append(roles);
    const lanes = el("div", "lanes");
    const stats = el("div", "stats");
    row.append(label, lanes, stats);
    service.view = { lanes, stats, svg: null };
    return row;
  }

  function interfaceBlock(iface) {
    const block = el("section", "iface");
    const head = el("div", "iface-head");
    head.append(el("span", "iface-type", iface.element.replace(/Interface$/, " interface")));
    head.append(el("span", "iface-id", iface.name || iface.id));
    const chips = el("span", "chips");
    for (const extra of iface.extras) {
      const chip = el("span", "chip");
      chip.append(el("span", "chip-name", words(extra.type)), el("b", "chip-value", "-"));
      extra.chip = chip;
      chips.append(chip);
    }
    head.append(chips);
    block.append(head);
    for (const service of iface.services) block.append(serviceRow(service));
    if (iface.served.length > 0) {
      // Handshakes this interface answers are drawn under their requester.
      const served = el("p", "served");
      served.append(el("span", "", "responds to "));
      iface.served.forEach((service, i) => {
        served.append(el("b", "", words(service.type)));
        const from = ` from ${service.request.device.name}${i + 1 < iface.served.length ? ", " : ""}`;
        served.append(el("span", "", from));
      });
      served.append(el("span", "muted", " (lanes under the requester)"));
      block.append(served);
    }
    return block;
  }

  function deviceCard(device) {
    const card = el("article", "device");
    const head = el("header", "device-head");
    head.append(el("h2", "", device.name), el("span", "uuid", device.uuid));
    device.badge = el("span", "badge", "-");
    head.append(device.badge);
    card.append(head);
    device.axis = el("div", "axis");
    if (device.interfaces.some((i) => i.services.length > 0)) card.append(device.axis);
    if (device.interfaces.length === 0) card.append(el("p", "none", "no interfaces"));
    for (const iface of device.interfaces) card.append(interfaceBlock(iface));
    return card;
  }

  function buildView() {
    const main = $("devices");
    main.replaceChildren(...page.model.devices.map(deviceCard));
    $("empty").hidden = page.model.devices.length > 0;
  }

  function latest(lane) {
    const s = lane.segments[lane.segments.length - 1];
    return s ? s.state : "UNAVAILABLE";
  }

  function drawAxis(device, start, width) {
    const step = page.windowMs <= 10000 ? 2000 : page.windowMs <= 30000 ? 5000
      : page.windowMs <= 60000 ? 10000 : page.windowMs <= 120000 ? 20000 : 60000;
    const ticks = [];
    for (let t = Math.ceil(start / step) * step; t <= start + page.windowMs; t += step) {
      const x = ((t - start) / page.windowMs) * width;
      const tick = el("span", "tick", clock(t));
      tick.style.left = `${x}px`;
      ticks.push(tick);
    }
    device.axis.replaceChildren(...ticks);
  }

  function drawLane(g, lane, y, start, end, X, latencyFor) {
    for (const s of lane.segments) {
      const t1 = s.t1 === null ? end : s.t1;
      if (t1 < start || s.t0 > end) continue;
      const x0 = X(Math.max(s.t0, start));
      const x1 = X(Math.min(t1, end));
      if (x1 - x0 < 0.5) continue;
      g.append(svg("rect", { x: x0, y, width: x1 - x0, height: LANE_H, class: `seg s-${s.state}` }));
      const text = latencyFor ? latencyFor(s) || s.state : s.state;
      if (x1 - x0 > text.length * 6.5 + 8) {
        const label = svg("text", { x: x0 + 4, y: y + LANE_H / 2 + 4, class: `seg-text t-${s.state}` });
        label.textContent = text;
        g.append(label);
      }
    }
  }

  // Step markers where there is room for them (a 150 ms handshake is a few
  // pixels wide at 60 s): a marker closer than MARK_GAP to the one before it
  // in its lane is left out; the statistics column gives every step's time.
  function drawMarks(g, service, start, end, X) {
    const MARK_GAP = 16;
    const laneOf = { 1: 0, 6: 0, 3: 1, 4: 1, 8: 1, F: 0.5 };
    const y = (lane) => lane * (LANE_H + GAP) + LANE_H / 2;
    // Detections (steps 2, 5, 7): the link from one side's transition to the other's.
    for (const h of [...service.done.slice(-60), service.current].filter(Boolean)) {
      if (X(h.t8 != null ? h.t8 : end) - X(h.t1) < 4 * MARK_GAP) continue;
      for (const [a, b, from, to] of [[h.t1, h.t3, 0, 1], [h.t4, h.t6, 1, 0], [h.t6, h.t8, 0, 1]]) {
        if (a == null || b == null || b < start || a > end) continue;
        g.append(svg("line", { x1: X(a), y1: y(from) + (from ? -LANE_H / 2 : LANE_H / 2),
                               x2: X(b), y2: y(to) + (to ? -LANE_H / 2 : LANE_H / 2), class: "link" }));
      }
    }
    const lastX = {};
    for (const m of service.marks) {
      if (m.t < start || m.t > end) continue;
      const lane = laneOf[m.step];
      const x = X(m.t);
      if (m.step !== "F" && lastX[lane] !== undefined && x - lastX[lane] < MARK_GAP) continue;
      lastX[lane] = x;
      g.append(svg("circle", { cx: x, cy: y(lane), r: 7, class: m.step === "F" ? "mark fail" : "mark" }));
      const label = svg("text", { x, y: y(lane) + 3.5, class: "mark-text" });
      label.textContent = m.step === "F" ? "!" : String(m.step);
      g.append(label);
    }
  }

  // A side's device lost (AVAILABILITY UNAVAILABLE): its lane is shaded.
  function drawOutage(g, entry, y, start, end, X) {
    if (!entry || !entry.device.availability) return;
    for (const s of entry.device.availability.lane.segments) {
      if (s.state !== "UNAVAILABLE") continue;
      const t1 = s.t1 === null ? end : s.t1;
      if (t1 < start || s.t0 > end) continue;
      const x0 = X(Math.max(s.t0, start));
      const width = Math.max(1, X(Math.min(t1, end)) - x0);
      g.append(svg("rect", { x: x0, y: y - 2, width, height: LANE_H + 4, class: "outage" }));
    }
  }

  function drawService(service, start, end) {
    const view = service.view;
    const width = Math.max(50, view.lanes.clientWidth);
    const height = 2 * LANE_H + GAP;
    if (!view.svg) {
      view.svg = svg("svg", { height, "aria-hidden": "true" });
      view.lanes.append(view.svg);
    }
    view.svg.setAttribute("width", width);
    view.svg.setAttribute("viewBox", `0 0 ${width} ${height}`);
    const X = (t) => ((t - start) / page.windowMs) * width;
    const g = svg("g");
    const byStart = new Map(service.done.concat(service.current || []).map((h) => [h.t1, h]));
    const latencyOf = (s) => {
      const h = s.state === "ACTIVE" ? byStart.get(s.t0) : null;
      return h && h.latency != null ? `ACTIVE, ${formatMs(h.latency)}` : null;
    };
    if (service.request) drawLane(g, service.request.lane, 0, start, end, X, latencyOf);
    if (service.response) drawLane(g, service.response.lane, LANE_H + GAP, start, end, X, null);
    drawOutage(g, service.request, 0, start, end, X);
    drawOutage(g, service.response, LANE_H + GAP, start, end, X);
    drawMarks(g, service, start, end, X);
    view.svg.replaceChildren(g);
    drawStats(service);
  }

  function drawStats(service) {
    const done = service.done.filter((h) => !h.failed && h.latency != null);
    const last = done[done.length - 1];
    const sorted = done.slice(-100).map((h) => h.latency).sort((a, b) => a - b);
    const median = sorted.length ? sorted[Math.floor(sorted.length / 2)] : null;
    const view = service.view;
    // The detections of the last complete handshake: steps 2, 5 and 7.
    const full = service.done.filter((h) => !h.failed && h.t8 != null);
    const h = full[full.length - 1];
    const detections = h
      ? `steps 2·5·7: ${Math.round(h.t3 - h.t1)} · ${Math.round(h.t6 - h.t4)} · ${Math.round(h.t8 - h.t6)} ms`
      : "steps 2·5·7: -";
    view.stats.replaceChildren(
      el("span", "big", formatMs(last && last.latency)),
      el("span", "small", `median ${formatMs(median)} · ${done.length} done`),
      el("span", "small", detections),
      el("span", service.fails ? "small failed" : "small", `${service.fails} FAIL`));
    view.stats.title = "latency: request ACTIVE to response COMPLETE (step 1 to step 4); " +
      "steps 2, 5, 7: how long each side took to see the other's transition";
  }

  function drawDevice(device, start, end) {
    const state = device.availability ? latest(device.availability.lane) : "-";
    device.badge.textContent = state === "UNAVAILABLE" ? "UNAVAILABLE: comms lost" : state;
    device.badge.className = `badge b-${state}`;
    const first = device.interfaces.flatMap((i) => i.services)[0];
    drawAxis(device, start, first ? Math.max(50, first.view.lanes.clientWidth) : 600);
    for (const iface of device.interfaces) {
      for (const extra of iface.extras) {
        const value = latest(extra.lane);
        extra.chip.lastChild.textContent = value;
        extra.chip.className = `chip c-${value}`;
      }
      for (const service of iface.services) drawService(service, start, end);
    }
  }

  function draw() {
    if (!page.model) return;
    const end = now();
    const start = end - page.windowMs;
    for (const device of page.model.devices) drawDevice(device, start, end);
    publish();
  }

  // What tests and tools read from the DOM.
  function publish() {
    const body = document.body;
    body.dataset.handshakes = String(counters.handshakes);
    body.dataset.fails = String(counters.fails);
    body.dataset.lastSequence = String(counters.lastSequence);
    const c = counters.lastComplete;
    if (c && !c.drawn) {
      c.drawn = true;
      body.dataset.lastCompleteSequence = String(c.sequence);
      body.dataset.lastCompleteLagMs = String(Math.round(now() - c.t));
    }
    $("counts").textContent =
      `${counters.handshakes} handshakes · ${counters.fails} FAIL · sequence ${counters.lastSequence}`;
  }

  // ---------- following the bridge ----------
  function setLink(state, text) {
    const link = $("link");
    link.dataset.link = state;
    link.textContent = text || state;
    document.body.dataset.state = state === "live" ? "live" : state === "error" ? "error" : "loading";
  }

  function noteHeader(header) {
    const created = Date.parse(header.creationTime);
    const skew = created - Date.now();
    page.skewMs = Math.abs(skew) > 2000 ? skew : 0;
  }

  async function load() {
    setLink("connecting");
    const probe = await fetchJson("probe?format=json");
    const h = probe.MTConnectDevices.Header;
    $("agent").textContent =
      `${h.sender} · MTConnect ${probe.MTConnectDevices.schemaVersion} · instance ${h.instanceId}`;
    page.model = buildModel(probe);
    MtcModel.reset();
    buildView();
    const current = await fetchJson("current?format=json");
    const ch = current.MTConnectStreams.Header;
    noteHeader(ch);
    page.instanceId = ch.instanceId;
    page.next = ch.nextSequence;
    const from = Math.max(ch.firstSequence, page.next - HISTORY);
    if (from < page.next) {
      apply(page.model, await fetchJson(`sample?format=json&from=${from}&to=${page.next}&count=${page.next - from}`));
    }
    // Items whose last change is older than the history start as /current says.
    for (const o of observationsOf(current)) {
      const item = page.model.items.get(o.dataItemId);
      if (item && item.lane.segments.length === 0) {
        pushState(item.lane, o.value === undefined ? "UNAVAILABLE" : String(o.value), parseTime(o.timestamp));
      }
    }
  }

  // Polls until the bridge restarts or the devices change (returns) or a
  // request fails (throws).
  async function follow() {
    for (;;) {
      const doc = await fetchJson(`sample?format=json&from=${page.next}&count=${PAGE}`);
      const h = doc.MTConnectStreams.Header;
      if (h.instanceId !== page.instanceId) return;
      noteHeader(h);
      const known = apply(page.model, doc);
      page.next = h.nextSequence;
      if (!known) return;
      setLink("live");
      if (page.readyMs === null) {
        draw();
        page.readyMs = Math.round(performance.now());
        document.body.dataset.readyMs = String(page.readyMs);
      }
      if (page.next > h.lastSequence) await sleep(POLL_MS);
    }
  }

  async function run() {
    for (;;) {
      try {
        await load();
        $("error").textContent = "";
        await follow();
      } catch (e) {
        setLink("error", "reconnecting");
        $("error").textContent = String(e.message || e);
        await sleep(RETRY_MS);
      }
    }
  }

  // ---------- controls ----------
  function setupControls() {
    $("window").addEventListener("change", (e) => {
      page.windowMs = Number(e.target.value) * 1000;
      draw();
    });
    $("pause").addEventListener("click", (e) => {
      page.paused = !page.paused;
      e.target.setAttribute("aria-pressed", String(page.paused));
      e.target.textContent = page.paused ? "resume" : "pause";
    });
    setInterval(() => {
      if (!page.paused && !document.hidden) draw();
    }, FRAME_MS);
    window.addEventListener("resize", () => draw());
  }

  function setupPatterns() {
    const defs = svg("svg", { width: 0, height: 0, class: "defs" });
    const pattern = svg("pattern", { id: "hatch", width: 6, height: 6, patternUnits: "userSpaceOnUse",
                                     patternTransform: "rotate(45)" });
    pattern.append(svg("rect", { width: 6, height: 6, class: "hatch-bg" }),
                   svg("line", { x1: 0, y1: 0, x2: 0, y2: 6, class: "hatch-line" }));
    const d = svg("defs");
    d.append(pattern);
    defs.append(d);
    document.body.append(defs);
  }

  window.mtcPage = page;  // for a console: the page's state
  setupPatterns();
  setupControls();
  run();
})();
