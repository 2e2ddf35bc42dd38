# SPDX-License-Identifier: GPL-3.0-or-later
"""Reads a .maxpat (Max cannot run here) and prints what the C++ test checks:
   'object TEXT' for every object box, 'sends ADDRESS' for every OSC address a message box or a
   [prepend /address] feeds towards [udpsend], 'on load TEXT' for every message box a [loadbang] feeds
   (directly or through a [t ...]). Exits 1 with the reason when the file is not a
   well-formed patcher: JSON, boxes with unique ids, patch lines between existing boxes' existing
   inlets and outlets."""
import json
import sys

with open(sys.argv[1]) as f:
    patcher = json.load(f)["patcher"]
boxes = {}
for entry in patcher["boxes"]:
    box = entry["box"]
    if box["id"] in boxes:
        sys.exit("box id %s twice" % box["id"])
    boxes[box["id"]] = box
for entry in patcher["lines"]:
    line = entry["patchline"]
    (source, outlet), (destination, inlet) = line["source"], line["destination"]
    if source not in boxes or destination not in boxes:
        sys.exit("patch line %s -> %s: no such box" % (source, destination))
    if outlet >= boxes[source]["numoutlets"] or inlet >= boxes[destination]["numinlets"]:
        sys.exit("patch line %s:%d -> %s:%d: no such outlet or inlet" % (source, outlet, destination, inlet))
for box in boxes.values():
    text = box.get("text", "")
    if box["maxclass"] == "newobj":
        print("object " + text)
        if text.startswith("prepend /"):
            print("sends " + text.split()[1])
    elif box["maxclass"] == "message" and text.startswith("/"):
        print("sends " + text.split()[0])
outlets = {}
for entry in patcher["lines"]:
    line = entry["patchline"]
    outlets.setdefault(line["source"][0], []).append(line["destination"][0])
for box in boxes.values():
    if box["maxclass"] == "newobj" and box.get("text") == "loadbang":
        pending, seen = list(outlets.get(box["id"], [])), set()
        while pending:
            target = boxes[pending.pop()]
            if target["id"] in seen:
                continue
            seen.add(target["id"])
            if target["maxclass"] == "message":
                print("on load " + target.get("text", ""))
            elif target.get("text", "").split()[:1] in (["t"], ["trigger"]):
                pending.extend(outlets.get(target["id"], []))
