#!/usr/bin/env python3
"""Makes catalogue/ (the furniture catalogue the server offers, GET /v1/catalogue) from Sweet Home 3D's
default catalogue in ../shared/data/floorplans/sweethome3d/catalogue (SOURCES.md section 5): the
entries listed in CHOSEN below, their OBJ models (with the .mtl of those in a folder) and icons copied
byte for byte, and catalogue/catalogue.json with each entry's id, name, category, size and elevation
in centimetres and modelRotation, read from DefaultFurnitureCatalog.properties. Also copies
default-materials.mtl. README.md and LICENSE in catalogue/ are written by hand.

    scripts/make-catalogue.py [SHARED_CATALOGUE_DIR]
"""
import json
import os
import re
import shutil
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SOURCE = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "..", "shared", "data", "floorplans", "sweethome3d", "catalogue")
OUT = os.path.join(ROOT, "catalogue")
PREFIX = "/com/eteks/sweethome3d/io/resources/"

# Furniture a room is furnished with: no doors or windows (the page cuts those into walls), no
# staircases, no bare light sources; small models first where two are alike.
CHOSEN = [
    "eTeks#bed140x190", "eTeks#bed90x190", "eTeks#bedsideTable", "eTeks#chest", "eTeks#wardrobe", "eTeks#crib",
    "eTeks#chair", "eTeks#chair2", "eTeks#stool", "eTeks#table", "eTeks#roundTable", "eTeks#squareTable",
    "eTeks#coffeeTable", "eTeks#desk", "eTeks#sofa", "eTeks#sofa2", "eTeks#armchair2", "eTeks#bookcase",
    "eTeks#tvUnit", "eTeks#flatTV", "eTeks#dresser", "eTeks#piano", "eTeks#fireplace", "eTeks#plant",
    "eTeks#fridge", "eTeks#cooker", "eTeks#sink", "eTeks#kitchenCabinet", "eTeks#dishwasher",
    "eTeks#toiletUnit", "eTeks#washbasin", "eTeks#bath", "eTeks#shower",
    "eTeks#lamp", "eTeks#floorUplight", "eTeks#pendantLamp", "eTeks#frame",
]


def snake(sh3d_id):
    name = sh3d_id.split("#", 1)[1]
    return re.sub(r"(?<=[a-z0-9])([A-Z])", r"_\1", name).lower()


def number(text):
    value = float(text)
    return int(value) if value == int(value) else value


def main():
    entries = {}
    with open(os.path.join(SOURCE, "DefaultFurnitureCatalog.properties"), encoding="latin-1") as f:
        for line in f:
            m = re.match(r"(\w+)#(\d+)=(.*)", line.strip())
            if m:
                entries.setdefault(int(m.group(2)), {})[m.group(1)] = m.group(3)
    by_id = {e["id"]: e for e in entries.values()}
    for folder in ("models", "icons"):
        shutil.rmtree(os.path.join(OUT, folder), ignore_errors=True)
        os.makedirs(os.path.join(OUT, folder))
    items = []
    for sh3d_id in CHOSEN:
        e = by_id[sh3d_id]
        slug = snake(sh3d_id)
        model = e["model"][len(PREFIX):]
        folder = os.path.dirname(model)
        if folder:  # a model in its own folder comes with its .mtl
            shutil.copytree(os.path.join(SOURCE, "resources", folder), os.path.join(OUT, "models", folder))
        else:
            shutil.copyfile(os.path.join(SOURCE, "resources", model), os.path.join(OUT, "models", model))
        shutil.copyfile(os.path.join(SOURCE, "resources", e["icon"][len(PREFIX):]), os.path.join(OUT, "icons", slug + ".png"))
        item = {"id": slug, "sh3d_id": sh3d_id, "name": e["name"], "category": e["category"],
                "width": number(e["width"]), "depth": number(e["depth"]), "height": number(e["height"]),
                "elevation": number(e.get("elevation", "0")), "model": "models/" + model, "icon": "icons/" + slug + ".png"}
        if "modelRotation" in e:
            item["model_rotation"] = e["modelRotation"]
        items.append(item)
    shutil.copyfile(os.path.join(SOURCE, "default-materials.mtl"), os.path.join(OUT, "default-materials.mtl"))
    document = {
        "source": "Sweet Home 3D 7.0.2 default furniture catalogue (DefaultFurnitureCatalog.properties, version 6.5)",
        "licence": "CC BY 3.0 (https://creativecommons.org/licenses/by/3.0/)",
        "attribution": "Furniture models: Sweet Home 3D default catalogue, © Emmanuel Puybaret / eTeks, CC BY 3.0 "
                       "(https://creativecommons.org/licenses/by/3.0/)",
        "units": "centimetres",
        "items": items,
    }
    with open(os.path.join(OUT, "catalogue.json"), "w", encoding="utf-8") as f:
        json.dump(document, f, indent=1, ensure_ascii=False)
        f.write("\n")
    size = sum(os.path.getsize(os.path.join(d, n)) for d, _, names in os.walk(OUT) for n in names)
    print(f"{len(items)} entries, {size} bytes in {OUT}")


if __name__ == "__main__":
    main()
