// The live page's model (bridge/web/, see index.html): devices,
// interfaces and services from the bridge's probe (MTConnect JSON), and the
// Part 5 handshakes (Table 1) followed from its observations. No drawing
// here: app.js draws, this file keeps the state.
"use strict";

const MtcModel = (() => {
  const KEEP_MS = 15 * 60 * 1000;  // history kept per lane
  const list = (group, name) => (group && Array.isArray(group[name]) ? group[name] : []);

  // What the observations added up to, for the page's figures.
  const counters = { handshakes: 0, fails: 0, lastSequence: 0, lastComplete: null };

  // MTConnect timestamps carry microseconds; Date.parse reads milliseconds.
  function parseTime(ts) {
    const ms = Date.parse(ts.length > 24 ? ts.slice(0, 23) + "Z" : ts);
    const micros = ts.length > 24 ? Number(ts.slice(23, 26)) / 1000 : 0;
    return ms + (Number.isFinite(micros) ? micros : 0);
  }

  // ---------- the model, from the probe ----------
  // A lane: the states of one data item as segments {state, t0, t1}.
  const newLane = () => ({ segments: [] });

  // A service: one request side and one response side of a type, from two
  // devices (the requester and the responder), shown as two lanes.
  function newService(type, request, response) {
    return { type, request, response, marks: [], done: [], current: null, fails: 0 };
  }

  function walkComponent(node, visit, iface) {
    for (const item of list(node.DataItems, "DataItem")) visit(item, iface);
    for (const [element, components] of Object.entries(node.Components || {})) {
      if (!Array.isArray(components)) continue;
      for (const c of components) {
        const inner = element.endsWith("Interface") ? { element, id: c.id, name: c.name } : iface;
        walkComponent(c, visit, inner);
      }
    }
  }

  function buildDevice(node) {
    const device = { name: node.name, uuid: node.uuid, availability: null, interfaces: [] };
    const interfaces = new Map();
    const items = [];
    walkComponent(node, (item, iface) => {
      const entry = { id: item.id, type: item.type, lane: newLane(), device, services: [] };
      items.push(entry);
      if (!iface) {
        if (item.type === "AVAILABILITY" && !device.availability) device.availability = entry;
        return;
      }
      if (!interfaces.has(iface.id)) {
        interfaces.set(iface.id, { ...iface, device, services: [], served: [], extras: [] });
      }
      entry.iface = interfaces.get(iface.id);
      if (item.subType === "REQUEST") entry.role = "request";
      else if (item.subType === "RESPONSE") entry.role = "response";
      else entry.iface.extras.push(entry);
    });
    device.interfaces = [...interfaces.values()];
    return { device, items };
  }

  // Pairs each request with the response of the same type in an interface
  // of the same kind on another device (Part 5 pairs interfaces by type; the
  // probe names no counterpart). A request is shown under its requester's
  // interface, with the responder's lane below it; a response nobody
  // requests gets a row of its own under its interface.
  function pairServices(items) {
    const sides = [...items.values()].filter((e) => e.role);
    const responses = sides.filter((e) => e.role === "response");
    for (const request of sides.filter((e) => e.role === "request")) {
      const matches = responses.filter((r) => r.type === request.type &&
        r.iface.element === request.iface.element && r.device !== request.device);
      const response = matches.length === 1 ? matches[0] : null;
      const service = newService(request.type, request, response);
      request.iface.services.push(service);
      request.services.push(service);
      if (response) {
        response.services.push(service);
        response.iface.served.push(service);
      }
    }
    for (const response of responses.filter((r) => r.services.length === 0)) {
      const service = newService(response.type, null, response);
      response.iface.services.push(service);
      response.services.push(service);
    }
  }

  function buildModel(probe) {
    const devicesNode = probe.MTConnectDevices.Devices || {};
    const model = { devices: [], items: new Map() };
    for (const node of list(devicesNode, "Device")) {
      const { device, items } = buildDevice(node);
      model.devices.push(device);
      for (const item of items) model.items.set(item.id, item);
    }
    pairServices(model.items);
    return model;
  }

  // ---------- observations ----------
  function observationsOf(doc) {
    const out = [];
    const streams = doc.MTConnectStreams.Streams || {};
    for (const deviceStream of list(streams, "DeviceStream")) {
      for (const componentStream of list(deviceStream, "ComponentStream")) {
        for (const group of ["Samples", "Events", "Condition"]) {
          for (const observations of Object.values(componentStream[group] || {})) {
            for (const o of observations) out.push(o);
          }
        }
      }
    }
    return out.sort((a, b) => a.sequence - b.sequence);
  }

  function pushState(lane, state, t) {
    const segments = lane.segments;
    const last = segments[segments.length - 1];
    if (last && last.state === state) return false;
    if (last) last.t1 = t;
    segments.push({ state, t0: t, t1: null });
    while (segments.length > 2 && segments[1].t1 !== null && segments[1].t1 < t - KEEP_MS) {
      segments.shift();
    }
    return true;
  }

  function fail(service, t) {
    service.fails += 1;
    counters.fails += 1;
    if (service.current) {
      service.current.failed = true;
      service.done.push(service.current);
      service.current = null;
    }
    service.marks.push({ step: "F", t });
  }

  // The handshake of Part 5 Table 1, as the two lanes show it.
  function onRequest(service, state, t) {
    if (state === "ACTIVE") {
      service.current = { t1: t };
      service.marks.push({ step: 1, t });
    } else if (state === "READY" && service.current && service.current.t4 != null) {
      service.current.t6 = t;
      service.marks.push({ step: 6, t });
    } else if (state === "FAIL") {
      fail(service, t);
    }
  }

  function onResponse(service, state, t, sequence) {
    const h = service.current;
    if (state === "ACTIVE" && h && h.t3 == null) {
      h.t3 = t;
      service.marks.push({ step: 3, t });
    } else if (state === "COMPLETE" && h && h.t4 == null) {
      h.t4 = t;
      h.latency = t - h.t1;
      service.done.push(h);
      service.marks.push({ step: 4, t });
      counters.handshakes += 1;
      counters.lastComplete = { sequence, t, drawn: false };
    } else if (state === "READY" && h && h.t6 != null) {
      h.t8 = t;
      service.marks.push({ step: 8, t });
      service.current = null;
    } else if (state === "FAIL") {
      fail(service, t);
    }
  }

  // Applies one document's observations to `model` in sequence order. Returns false
  // when one names an item the model lacks (the devices changed).
  function apply(model, doc) {
    let known = true;
    for (const o of observationsOf(doc)) {
      counters.lastSequence = Math.max(counters.lastSequence, o.sequence);
      const item = model.items.get(o.dataItemId);
      if (!item) {
        known = false;
        continue;
      }
      const state = o.value === undefined ? "UNAVAILABLE" : String(o.value);
      const t = parseTime(o.timestamp);
      if (!pushState(item.lane, state, t)) continue;
      for (const service of item.services) {
        if (item.role === "request") onRequest(service, state, t);
        else onResponse(service, state, t, o.sequence);
        while (service.marks.length > 0 && service.marks[0].t < t - KEEP_MS) service.marks.shift();
        if (service.done.length > 500) service.done.splice(0, 250);
      }
    }
    return known;
  }

  function reset() {
    Object.assign(counters, { handshakes: 0, fails: 0, lastComplete: null });
  }

  return { buildModel, observationsOf, pushState, apply, parseTime, list, counters, reset };
})();
