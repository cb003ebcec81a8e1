#!/usr/bin/env python3
"""A fixed, paced load whose CPU tells how fast the machine is right now.

The endurance run judges whether a process's CPU grows with the run's age.
On a shared virtual machine the same work can cost twice the CPU for minutes
at a time (other guests on the host); every process of the cell then rises
together, and a leak cannot be told from a slow host by the processes alone.
This process does the same work every tick for the whole run: wakeups of a
second thread over a socket pair (system calls and context switches, as DDS
does) and some hashing (plain computation). The sampler measures it like the
others; its last/first CPU ratio is the machine's own drift, and endurance.py
judges the others relative to it.

No network traffic: an AF_UNIX socket pair inside this process. Runs until
SIGINT/SIGTERM or until its parent dies.
"""
import argparse
import hashlib
import signal
import socket
import sys
import threading
import time

BUFFER = bytes(range(256)) * 128  # 32 KiB to hash


def echo(sock):
    """Sends back every byte it receives until the peer closes."""
    while True:
        data = sock.recv(64)
        if not data:
            return
        sock.sendall(data)


def one_tick(sock, round_trips, hashes):
    for _ in range(round_trips):
        sock.sendall(b"x")
        if sock.recv(64) != b"x":
            raise RuntimeError("reference_load: the echo thread answered wrongly")
    digest = b""
    for _ in range(hashes):
        digest = hashlib.sha256(BUFFER + digest).digest()
    return digest


def main(argv):
    p = argparse.ArgumentParser(prog="reference_load.py", description=__doc__.split("\n\n")[0])
    p.add_argument("--tick-ms", type=float, default=20.0, help="period of the work (default 20)")
    p.add_argument("--round-trips", type=int, default=8,
                   help="thread wakeups there and back per tick (default 8)")
    p.add_argument("--hashes", type=int, default=4, help="SHA-256 of 32 KiB per tick (default 4)")
    args = p.parse_args(argv)
    if args.tick_ms <= 0 or args.round_trips < 0 or args.hashes < 0:
        p.error("need --tick-ms > 0 and non-negative counts")
    # A plain flag: Event.set() in a signal handler can deadlock on the lock
    # that the interrupted Event.wait() holds.
    stopping = []
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, lambda *_: stopping.append(True))
    mine, theirs = socket.socketpair()
    threading.Thread(target=echo, args=(theirs,), daemon=True).start()
    period = args.tick_ms / 1000.0
    next_at = time.monotonic()
    # Pacing, not synchronisation: the work is due at fixed instants.
    while not stopping:
        one_tick(mine, args.round_trips, args.hashes)
        next_at += period
        time.sleep(max(0.0, next_at - time.monotonic()))
    mine.close()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
