#!/usr/bin/env python3
"""Checks of the endurance harness's own judgement (benchmarks/endurance):
the stream checker must see every kind of sequence fault, and the cell log
reader must tell a false alarm from a LOST line after the stop, and the CPU
verdict must tell a leak from a slow host. No DDS, no network: synthetic
parts, log lines and CPU figures."""
import io
import os
import sys
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "benchmarks", "endurance"))

import cell_log  # noqa: E402
import endurance  # noqa: E402
import stream_check  # noqa: E402

NS = "urn:mtconnect.org:MTConnectStreams:1.6"


def part(next_seq, *observations):
    """A MTConnectStreams document; observations are (sequence, value), in
    document order (grouped by component, not by sequence)."""
    items = "".join('<MaterialLoad dataItemId="i%d" sequence="%d">%s</MaterialLoad>' % (s, s, v)
                    for s, v in observations)
    return ('<MTConnectStreams xmlns="%s"><Header firstSequence="1" nextSequence="%d" '
            'lastSequence="%d"/><Streams><DeviceStream name="d" uuid="d"><ComponentStream '
            'component="Interface"><Events>%s</Events></ComponentStream></DeviceStream>'
            '</Streams></MTConnectStreams>' % (NS, next_seq, max(next_seq - 1, 0), items)).encode()


def checked(*parts):
    check = stream_check.StreamCheck(port=0)
    for body in parts:
        check.check_part(body)
    return check


class StreamSequences(unittest.TestCase):
    def test_consecutive_parts_in_any_document_order_pass(self):
        c = checked(part(4, (2, "READY"), (1, "READY"), (3, "ACTIVE")), part(4),
                    part(6, (5, "READY"), (4, "NOT_READY")))
        self.assertTrue(c.ok(), c.summary())
        self.assertEqual((c.parts, c.empty_parts, c.observations), (3, 1, 5))
        self.assertEqual((c.first_sequence, c.next_sequence), (1, 6))

    def test_a_part_that_does_not_start_at_the_previous_next_sequence_is_a_gap(self):
        c = checked(part(3, (1, "READY"), (2, "READY")), part(6, (4, "READY"), (5, "READY")))
        self.assertEqual((c.gap_count, c.regression_count), (1, 0))
        self.assertEqual(c.gaps[0], {"expected": 3, "got": 4, "kind": "gap"})
        self.assertFalse(c.ok())

    def test_a_missing_sequence_inside_a_part_is_a_gap(self):
        c = checked(part(5, (1, "READY"), (2, "READY"), (4, "READY")))
        self.assertEqual(c.gap_count, 1)
        self.assertEqual(c.gaps[0], {"expected": 3, "got": 4, "kind": "gap"})
        self.assertFalse(c.ok())

    def test_a_repeated_sequence_is_a_regression(self):
        c = checked(part(3, (1, "READY"), (2, "READY")), part(4, (2, "READY"), (3, "READY")))
        self.assertGreaterEqual(c.regression_count, 1)
        self.assertFalse(c.ok())

    def test_next_sequence_going_back_is_a_regression(self):
        c = checked(part(3, (1, "READY"), (2, "READY")), part(2))
        self.assertEqual(c.regression_count, 1)
        self.assertFalse(c.ok())

    def test_an_empty_part_that_moves_next_sequence_skipped_observations(self):
        c = checked(part(3, (1, "READY"), (2, "READY")), part(5))
        self.assertEqual(c.gap_count, 1)

    def test_an_error_part_fails_the_check(self):
        body = ('<MTConnectError xmlns="urn:mtconnect.org:MTConnectError:1.6"><Header/><Errors>'
                '<Error errorCode="OUT_OF_RANGE">the stream fell behind</Error></Errors>'
                '</MTConnectError>').encode()
        c = checked(part(2, (1, "READY")), body)
        self.assertIn("OUT_OF_RANGE", c.errors[0])
        self.assertFalse(c.ok())

    def test_unavailable_values_are_counted(self):
        c = checked(part(3, (1, "UNAVAILABLE"), (2, "READY")))
        self.assertEqual(c.unavailable, 1)
        self.assertEqual(c.summary()["unavailable_values_per_minute"], {"0": 1})

    def test_multipart_stream_is_split_by_content_length(self):
        a, b = part(2, (1, "READY")), part(3, (2, "ACTIVE"))
        stream = b"".join(b"--XYZ\r\nContent-type: text/xml\r\nContent-length: %d\r\n\r\n%s\r\n"
                          % (len(body), body) for body in (a, b)) + b"--XYZ--\r\n"
        c = stream_check.StreamCheck(port=0)
        c._read_parts(io.BytesIO(stream), "XYZ")
        self.assertTrue(c.ended_cleanly)
        self.assertEqual((c.parts, c.observations, c.next_sequence), (2, 2, 3))
        self.assertTrue(c.ok(), c.summary())


def log_of(*lines):
    log = cell_log.CellLog(None, None, None, 0)
    for i, text in enumerate(lines):
        log.parse("23:00:%02d.000  %s" % (i % 60, text), float(i))
    return log.report(), log


class CellLog(unittest.TestCase):
    def test_lost_before_the_stop_is_a_false_alarm_and_after_it_is_not(self):
        report, _ = log_of(
            "robot   | link door -> cell-machine: LOST (deadline missed: nothing heard for 251 ms)",
            "robot   | link door -> cell-machine: UP (value received)",
            "cell    | stop requested: stopping every station",
            "feeder  | link material_handler -> cell-machine: LOST (disposed)")
        self.assertEqual((report["false_alarms"], report["lost_after_stop"]), (1, 1))
        self.assertEqual(report["false_alarm_lines"][0]["station"], "robot")

    def test_handshakes_injected_and_other_failures(self):
        report, log = log_of(
            "cell    | stations started: machine pid 12, robot pid 11, feeder pid 10 (DDS domain 5)",
            "feeder  | !! MATERIAL_FEED: injected failure, scenario 1 (no bar stock detected)",
            "machine | MATERIAL_FEED   FAILED (both sides FAIL) after 6.6 ms",
            "machine | MATERIAL_LOAD   done in 918.2 ms, both READY",
            "robot   |   OPEN_DOOR       done in 160.1 ms, both READY",
            "machine | cell summary: 3 cycles complete, 9 handshakes by the machine, 2 failures "
            "(1 injected, 1 other), 2 recovered")
        self.assertEqual(log.station_pids, {"machine": 12, "robot": 11, "feeder": 10})
        self.assertEqual(report["handshakes_completed"], 2)
        self.assertEqual(report["handshakes_by_service"], {"MATERIAL_LOAD": 1, "OPEN_DOOR": 1})
        self.assertEqual(report["injected_failures"], 1)
        self.assertEqual(report["requester_failures_logged"], 1)
        self.assertEqual(report["other_failures"], 1)
        self.assertFalse(report["machine_summary"]["stopped_on_unrecovered_failure"])

    def test_an_unrecovered_failure_is_reported(self):
        report, _ = log_of("machine | MATERIAL_LOAD   request could not recover")
        self.assertEqual(len(report["unrecovered_or_dead"]), 1)
        self.assertIsNone(report["other_failures"])  # no summary: the verdict fails


def cpu(first_last_by_name):
    return [{"name": n, "cpu_first_window_pct": f, "cpu_last_window_pct": l}
            for n, (f, l) in first_last_by_name.items()]


class CpuFlat(unittest.TestCase):
    def test_every_process_rising_with_the_reference_is_a_slow_host(self):
        # The figures of a CI run on a host that slowed in its last minute.
        v = endurance.cpu_flat(1.5, cpu({"machine": (2.205, 4.017), "robot": (1.67, 2.983),
                                         "feeder": (1.37, 2.667), "bridge": (1.821, 3.517),
                                         "reference": (1.9, 3.6)}))
        self.assertTrue(v["pass"], v["detail"])
        self.assertAlmostEqual(v["machine_drift"], 3.6 / 1.9, places=3)

    def test_the_same_rise_against_a_flat_reference_is_a_leak(self):
        v = endurance.cpu_flat(1.5, cpu({"machine": (2.205, 4.017), "bridge": (1.8, 1.9),
                                         "reference": (1.9, 1.95)}))
        self.assertFalse(v["pass"], v["detail"])

    def test_one_process_outgrowing_the_drift_fails(self):
        v = endurance.cpu_flat(1.5, cpu({"machine": (2.0, 6.5), "robot": (1.6, 2.4),
                                         "reference": (1.9, 3.8)}))
        self.assertFalse(v["pass"], v["detail"])

    def test_a_faster_machine_never_tightens_the_limit(self):
        v = endurance.cpu_flat(1.5, cpu({"machine": (2.0, 2.9), "reference": (2.0, 1.0)}))
        self.assertTrue(v["pass"], v["detail"])
        self.assertEqual(v["machine_drift"], 1.0)

    def test_without_the_reference_the_verdict_fails(self):
        v = endurance.cpu_flat(1.5, cpu({"machine": (2.0, 2.1)}))
        self.assertFalse(v["pass"], v["detail"])
        self.assertIsNone(v["machine_drift"])


if __name__ == "__main__":
    unittest.main()
