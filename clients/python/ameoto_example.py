#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Talk to ameotod from Python with pyliblo (Debian: python3-liblo).

Sets the rain rate, sends drops now, sends drops in timed OSC bundles (each played at its
timetag, to the sample), and prints the server's /status.reply field by field.

    /usr/bin/python3 clients/python/ameoto_example.py                 # ameotod on 127.0.0.1:7770
    /usr/bin/python3 clients/python/ameoto_example.py --port 7771 --rate 0 --drops 0 \
        --bundle-in 0.5 --bundle-spacing 0.25 --bundle-drops 3

Units: rain rate mm/h, drop diameter mm, speed m/s (0 = terminal speed), positions m, times s.
Exit status: 0 done; 1 the server refused something (/fail) or did not answer; 2 usage error.
See docs/clients.md and docs/PROTOCOL.md.
"""

import argparse
import sys
import time

import liblo

# /status.reply ,fffiiiiififfsfif: the field names ameoto status --json uses (docs/PROTOCOL.md).
STATUS_FIELDS = (
    "cpu_average_percent", "cpu_peak_percent", "drops_per_second",
    "active_drops_full", "active_drops_template", "active_drops_texture",
    "xruns", "late_bundles", "sample_rate_hz", "block_size_frames",
    "seconds_rendered", "rain_rate_mm_per_h", "backend", "clock_ppm", "clipped_samples",
    "full_scale_db_spl",
)
STATUS_TYPES = "fffiiiiififfsfif"


class AmeotoClient:
    """A reply port of our own: the server answers to the port a request came from."""

    def __init__(self, host, port):
        self.target = liblo.Address(host, port, liblo.UDP)
        self.server = liblo.Server(0, liblo.UDP)   # 0: any free port
        self.replies = []
        self.server.add_method(None, None, self._on_reply)

    def _on_reply(self, path, args, types, source):
        self.replies.append((path, types, args))

    def send(self, path, *args):
        self.server.send(self.target, path, *args)

    def send_bundle(self, ntp_time, *messages):
        self.server.send(self.target, liblo.Bundle(ntp_time, *messages))

    def wait_for(self, path, timeout_s=2.0):
        """The next reply at path; a /fail on the way ends the program with its reason."""
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            self.server.recv(50)
            while self.replies:
                got = self.replies.pop(0)
                if got[0] == "/fail":
                    sys.exit("ameotod refused %s: %s" % (got[2][0], got[2][1]))
                if got[0] == path:
                    return got
        sys.exit("no %s from ameotod within %.1f s: is it running on that port?" % (path, timeout_s))

    def status(self):
        self.send("/status")
        _, types, args = self.wait_for("/status.reply")
        if types != STATUS_TYPES:
            sys.exit("/status.reply has types ,%s, expected ,%s: a different ameotod version?" % (types, STATUS_TYPES))
        return dict(zip(STATUS_FIELDS, args))


def drop_message(diameter_mm, x_m, y_m, speed_m_per_s=0.0):
    # Explicit 'f' tags: ameotod coerces numbers anyway, but floats are what the table documents.
    return liblo.Message("/drop", ("f", diameter_mm), ("f", speed_m_per_s), ("f", x_m), ("f", y_m))


def main():
    p = argparse.ArgumentParser(description="ameotod from Python: rain rate, drops, a timed bundle, /status")
    p.add_argument("--host", default="127.0.0.1")
    p.add_argument("--port", type=int, default=7770, help="ameotod's UDP port (default 7770)")
    p.add_argument("--rate", type=float, default=10.0, help="rain rate, mm/h, 0..500 (default 10)")
    p.add_argument("--drops", type=int, default=2, help="drops to play at once (default 2)")
    p.add_argument("--bundle-in", type=float, default=0.5,
                   help="the first timed drop this many seconds from now (default 0.5)")
    p.add_argument("--bundle-spacing", type=float, default=0.25,
                   help="seconds between timed drops (default 0.25)")
    p.add_argument("--bundle-drops", type=int, default=3, help="timed drops, one bundle each (default 3)")
    p.add_argument("--diameter", type=float, default=3.0, help="drop diameter, mm, 0.1..8 (default 3)")
    a = p.parse_args()

    c = AmeotoClient(a.host, a.port)
    c.send("/rain/rate", ("f", a.rate))
    for i in range(a.drops):
        c.send(drop_message(a.diameter, 0.2, -0.1 + 0.2 * i))
    # /sync answers once everything sent before it is applied: a /fail for the rate or a drop
    # would have arrived first.
    c.send("/sync", 1)
    c.wait_for("/synced")

    # Timed drops: liblo.time() is the wall clock as an OSC (NTP) time; each bundle's drop is
    # played at the sample its timetag falls on, however late the datagram travels (if it is
    # not later than the time itself).
    # The bundles go out back to back, the printing after.
    start = liblo.time() + a.bundle_in
    times = [start + i * a.bundle_spacing for i in range(a.bundle_drops)]
    for when in times:
        c.send_bundle(when, drop_message(a.diameter, 0.2, 0.0))
    for i, when in enumerate(times):
        print("bundle %d: /drop %g mm at NTP %.6f" % (i + 1, a.diameter, when))
    sys.stdout.flush()
    remaining = start + (a.bundle_drops - 1) * a.bundle_spacing - liblo.time()
    if remaining > 0:
        time.sleep(remaining + 0.1)
    c.send("/sync", 2)
    c.wait_for("/synced")

    for name, value in c.status().items():
        print("%s %s" % (name, value))
    return 0


if __name__ == "__main__":
    sys.exit(main())
