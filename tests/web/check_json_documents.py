#!/usr/bin/env python3
"""MTConnect JSON against XML over a running cell (issue 12): for the same
requests, /probe, /current and /sample answered as JSON (format=json, and
Accept: application/json) hold the same devices, components, data items,
observations, sequences and header fields as the XML, in the layout of the
reference agent's JSON version 2; errors too. Runs inside the loopback-only
namespace (ctest: scripts/netns-run.sh)."""
import argparse
import json
import sys
import unittest
import xml.etree.ElementTree as ET

from live_cell import LiveCell

ARGS = None
CELL = None


def local(tag):
    return tag.split("}", 1)[-1]


def xml_doc(path):
    status, ctype, body = CELL.get(path)
    assert ctype == "text/xml", (path, ctype)
    return status, ET.fromstring(body)


def json_doc(path, by_accept=False):
    if by_accept:
        status, ctype, body = CELL.get(path, accept="application/json")
    else:
        status, ctype, body = CELL.get(path + ("&" if "?" in path else "?") + "format=json")
    assert ctype == "application/json", (path, ctype)
    return status, json.loads(body)


def walk_json(node, visit, name=None):
    """Every object of a JSON document with the member name it sits under
    (array elements take their array's name)."""
    if isinstance(node, dict):
        visit(name, node)
        for key, value in node.items():
            walk_json(value, visit, key)
    elif isinstance(node, list):
        for value in node:
            walk_json(value, visit, name)


def xml_items(root):
    return sorted((d.get("id"), d.get("type"), d.get("subType"), d.get("category"), d.get("name"))
                  for d in root.iter() if local(d.tag) == "DataItem")


def json_items(doc):
    out = []
    walk_json(doc, lambda name, o: out.append(
        (o.get("id"), o.get("type"), o.get("subType"), o.get("category"), o.get("name")))
        if name == "DataItem" else None)
    return sorted(out)


def xml_components(root):
    devices = next(e for e in root if local(e.tag) == "Devices")
    return sorted((local(e.tag), e.get("id"), e.get("name")) for e in devices.iter()
                  if e.get("id") and local(e.tag) not in ("DataItem",))


def json_components(doc):
    out = []

    def visit(name, o):
        if name and name not in ("DataItem", "Header") and "id" in o and name[0].isupper():
            out.append((name, o["id"], o.get("name")))
    walk_json(doc["MTConnectDevices"]["Devices"], visit)
    return sorted(out)


def xml_observations(root):
    out = []
    streams = next(e for e in root if local(e.tag) == "Streams")
    for ds in streams:
        for cs in ds:
            for group in cs:
                for o in group:
                    out.append((ds.get("uuid"), cs.get("componentId"), local(group.tag), local(o.tag),
                                o.get("dataItemId"), int(o.get("sequence")), o.get("timestamp"),
                                o.get("subType"), o.get("name"),
                                None if local(group.tag) == "Condition" else (o.text or "")))
    return sorted(out, key=lambda t: t[5])


def json_observations(doc):
    out = []
    streams = doc["MTConnectStreams"]["Streams"]
    for ds in streams.get("DeviceStream", []):
        for cs in ds["ComponentStream"]:
            for group in ("Samples", "Events", "Condition"):
                for element, observations in cs.get(group, {}).items():
                    for o in observations:
                        value = o.get("value")
                        if isinstance(value, (int, float)):
                            value = repr(value)
                        out.append((ds["uuid"], cs["componentId"], group, element, o["dataItemId"],
                                    o["sequence"], o["timestamp"], o.get("subType"), o.get("name"),
                                    None if group == "Condition" else value))
    return sorted(out, key=lambda t: t[5])


def xml_header(root):
    return next(e for e in root if local(e.tag) == "Header").attrib


class JsonMatchesXml(unittest.TestCase):
    def assert_header(self, xml_root, jdoc, kind, stream=False):
        xh = xml_header(xml_root)
        body = jdoc[kind]
        jh = body["Header"]
        self.assertEqual(body["jsonVersion"], 2)
        for key in ("sender", "version"):
            self.assertEqual(jh[key], xh[key], key)
        for key in ("instanceId", "bufferSize"):
            self.assertEqual(jh[key], int(xh[key]), key)
            self.assertIsInstance(jh[key], int)
        self.assertIs(jh["testIndicator"], False)
        if stream:
            # The cell is running: the JSON was asked for after the XML.
            self.assertGreaterEqual(jh["lastSequence"], int(xh["lastSequence"]))
            self.assertGreaterEqual(jh["firstSequence"], int(xh["firstSequence"]))

    def test_probe(self):
        for path in ("/probe", "/machine/probe", "/robot"):
            _, root = xml_doc(path)
            for by_accept in (False, True):
                status, jdoc = json_doc(path, by_accept)
                self.assertEqual(status, 200)
                self.assert_header(root, jdoc, "MTConnectDevices")
                self.assertEqual(jdoc["MTConnectDevices"]["schemaVersion"],
                                 xml_header(root)["version"][:3])
                self.assertEqual(json_items(jdoc), xml_items(root), path)
                self.assertEqual(json_components(jdoc), xml_components(root), path)
                devices = jdoc["MTConnectDevices"]["Devices"]["Device"]
                self.assertEqual([(d["name"], d["uuid"]) for d in devices],
                                 [(d.get("name"), d.get("uuid")) for d in root.iter()
                                  if local(d.tag) == "Device"])

    def compare_streams(self, path):
        status_x, root = xml_doc(path)
        status_j, jdoc = json_doc(path)
        self.assertEqual((status_j, status_x), (200, 200), path)
        self.assert_header(root, jdoc, "MTConnectStreams", stream=True)
        xh, jh = xml_header(root), jdoc["MTConnectStreams"]["Header"]
        self.assertEqual(jh["nextSequence"], int(xh["nextSequence"]), path)
        xo, jo = xml_observations(root), json_observations(jdoc)
        self.assertEqual(jo, xo, path)
        # The reference agent lists only devices with observations.
        with_data = sorted({o[0] for o in xo})
        self.assertEqual(sorted(d["uuid"] for d in jdoc["MTConnectStreams"]["Streams"]
                                .get("DeviceStream", [])), with_data, path)
        return xo

    def test_current_and_sample(self):
        _, cur = json_doc("/current")
        h = cur["MTConnectStreams"]["Header"]
        last = h["lastSequence"]
        first = h["firstSequence"]
        frm = max(first, last - 300)
        observed = self.compare_streams("/current?at=%d" % last)
        self.assertGreater(len(observed), 10)
        sample = self.compare_streams("/sample?from=%d&to=%d&count=300" % (frm, last))
        self.assertEqual([o[5] for o in sample], list(range(frm, last)))
        self.compare_streams("/machine/sample?from=%d&to=%d&count=300" % (frm, last))
        self.compare_streams("/sample?from=%d&to=%d&count=300&path=//DataItem[@subType='RESPONSE']"
                             % (frm, last))
        self.compare_streams("/sample?from=%d&to=%d&count=20" % (frm, last))

    def test_errors(self):
        for path, code, status in (("/sample?count=0", "OUT_OF_RANGE", 400),
                                   ("/nothing/probe", "NO_DEVICE", 404),
                                   ("/sample?from=x", "INVALID_REQUEST", 400),
                                   ("/current?path=//Nothing", "INVALID_PATH", 400)):
            xs, root = xml_doc(path)
            js, jdoc = json_doc(path)
            self.assertEqual((js, xs), (status, status), path)
            xml_error = next(e for e in root.iter() if local(e.tag) == "Error")
            errors = jdoc["MTConnectError"]["Errors"]["Error"]
            self.assertEqual(len(errors), 1)
            self.assertEqual(errors[0]["errorCode"], xml_error.get("errorCode"))
            self.assertEqual(errors[0]["errorCode"], code)
            self.assertEqual(errors[0]["value"], xml_error.text)
            self.assert_header(root, jdoc, "MTConnectError")


def main():
    global ARGS, CELL
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--build", required=True)
    p.add_argument("--domain", type=int, required=True)
    p.add_argument("--port", type=int, required=True)
    ARGS, rest = p.parse_known_args()
    with LiveCell(ARGS.build, ARGS.domain, ARGS.port) as cell:
        CELL = cell
        # Three devices announced and a few hundred observations buffered.
        cell.wait_for("three devices", lambda: len(
            cell.json("/probe")[1]["MTConnectDevices"]["Devices"].get("Device", [])) == 3)
        cell.wait_for("300 observations", lambda: cell.json("/current")[1]
                      ["MTConnectStreams"]["Header"]["lastSequence"] > 400)
        result = unittest.main(argv=[sys.argv[0]] + rest, exit=False, verbosity=2).result
    return 0 if result.wasSuccessful() else 1


if __name__ == "__main__":
    sys.exit(main())
