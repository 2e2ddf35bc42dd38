"""Reads a .maxpat (Max cannot run here) and prints what the C++ test checks:
   'object TEXT' for every object box, 'sends ADDRESS' for every OSC address a message box or a
   [prepend /address] feeds towards [udpsend]. Exits 1 with the reason when the file is not a
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
