#!/usr/bin/env python3
"""Checks that every layer includes only itself and the layers below it (docs/architecture.md).

Each source file under a layer's folder may include project headers from its own layer and the
layers below it, and only the third-party headers its layer is allowed. Prints every violation as
FILE:LINE and exits 1 when there is one.
"""
import pathlib
import re
import sys

# Lowest first. A layer may include its own headers and those of every earlier layer.
LAYERS = [
    ("render/core", ["glm/", "stb_", "zlib.h"]),
    ("render/pipelines", ["glm/"]),
    ("render/scene_io", ["glm/", "nlohmann/"]),
    ("render/import", ["glm/", "nlohmann/", "pugixml.hpp", "zip.h"]),
    ("server", ["glm/", "nlohmann/", "httplib.h"]),
    ("cli", ["glm/", "nlohmann/", "httplib.h"]),
]
THIRD_PARTY = ("glm/", "nlohmann/", "stb_", "zlib.h", "pugixml", "zip.h", "httplib.h")
INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]')


def layer_of(path: str):
    for rank, (folder, _) in enumerate(LAYERS):
        if path.startswith(folder + "/"):
            return rank
    return None


def main(root: pathlib.Path) -> int:
    problems = []
    checked = 0
    for rank, (folder, allowed) in enumerate(LAYERS):
        for source in sorted((root / folder).glob("*.[ch]pp")):
            checked += 1
            relative = source.relative_to(root).as_posix()
            for number, line in enumerate(source.read_text().splitlines(), 1):
                match = INCLUDE.match(line)
                if not match:
                    continue
                quote, name = match.groups()
                if quote == '"':
                    target = layer_of(name)
                    if target is not None and target > rank:
                        problems.append(f"{relative}:{number}: includes {name}, a layer above {folder}/")
                elif name.startswith(THIRD_PARTY) and not name.startswith(tuple(allowed)):
                    problems.append(f"{relative}:{number}: includes <{name}>, which {folder}/ may not use")
    for problem in problems:
        print(problem)
    print(f"{checked} files checked, {len(problems)} includes against the layering")
    return 1 if problems or checked == 0 else 0


if __name__ == "__main__":
    sys.exit(main(pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()))
