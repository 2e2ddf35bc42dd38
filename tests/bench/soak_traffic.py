# SPDX-License-Identifier: GPL-3.0-or-later
"""The soak's OSC traffic (tests/bench/soak, tests/bench/heap-per-scene), in one place.

Interface:
    message(address, *args) -> bytes      an OSC message; float, int and str arguments
    parse(packet) -> (address, args)      the inverse, for i, f, h and s arguments
    SCENES                                the built-in scenes, in the order loaded
    one_second(t, send)                   second t's requests: a random rain rate (0-40 mm/h) and
                                          wind (0-12 m/s, any direction, gusts 0-0.5), 4 /drop anywhere
                                          on the umbrella; every 30 s /scene/load of the next scene.
                                          send(address, *args, reply=None) sends one; returns the
                                          scene loaded this second, or None. Call random.seed first.
"""
import random
import struct

SCENES = ["umbrella", "pond", "tin-roof", "forest", "street"]


def _pad(b):
    return b + b"\0" * (4 - len(b) % 4)


def message(address, *args):
    tags, data = ",", b""
    for a in args:
        if isinstance(a, float):
            tags += "f"; data += struct.pack(">f", a)
        elif isinstance(a, int):
            tags += "i"; data += struct.pack(">i", a)
        else:
            tags += "s"; data += _pad(a.encode())
    return _pad(address.encode()) + _pad(tags.encode()) + data


def parse(packet):
    end = packet.index(b"\0")
    address = packet[:end].decode()
    pos = (end + 4) & ~3
    tend = packet.index(b"\0", pos)
    tags = packet[pos + 1:tend].decode()
    pos = (tend + 4) & ~3
    args = []
    for t in tags:
        if t in "if":
            args.append(struct.unpack(">i" if t == "i" else ">f", packet[pos:pos + 4])[0]); pos += 4
        elif t == "h":
            args.append(struct.unpack(">q", packet[pos:pos + 8])[0]); pos += 8
        elif t == "s":
            e = packet.index(b"\0", pos); args.append(packet[pos:e].decode()); pos = (e + 4) & ~3
    return address, args


def one_second(t, send):
    send("/rain/rate", random.uniform(0.0, 40.0))
    send("/rain/wind", random.uniform(0.0, 12.0), random.uniform(-180.0, 180.0), random.uniform(0.0, 0.5))
    for _ in range(4):   # drops anywhere on the umbrella; refused politely when the scene has none
        send("/drop", random.uniform(0.5, 5.0), 0.0, random.uniform(-0.25, 0.25), random.uniform(-0.25, 0.25))
    if t % 30 == 0:
        scene = SCENES[(t // 30) % len(SCENES)]
        send("/scene/load", scene, reply="/done")
        return scene
    return None
