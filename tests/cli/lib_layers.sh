# The include rule of lib/README.md, read from its table: a file in a folder of lib/
# includes our headers only from the folders that folder's row names (or vdbgi.h); every
# source sits in a folder with a row; C++ only in shim/; OpenVDB, OpenImageIO and the glTF
# library only in shim/, Embree only in scene/, assimp only in scene/; apps/ include
# vdbgi.h (gi-bench vdbgi_bench.h too) and their own headers only. Each include against
# the rule is named.
cd "$ROOT" || exit 1
python3 - <<'PY'
import os
import re

rows = {}
for line in open("lib/README.md"):
    cells = [c.strip() for c in line.strip().strip("|").split("|")]
    if len(cells) == 3 and cells[0] not in ("folder", "---") and not cells[0].startswith("-"):
        rows[cells[0]] = {f.strip() for f in cells[2].split(",") if f.strip()} | {cells[0]}
print("folders:", " ".join(rows))

home = {}  # header or source name -> folder
bad = []
sources = []
for entry in sorted(os.listdir("lib")):
    path = os.path.join("lib", entry)
    if os.path.isdir(path):
        if entry not in rows:
            bad.append(f"lib/{entry}/: a folder without a row in lib/README.md")
            continue
        for name in sorted(os.listdir(path)):
            if name in home:
                bad.append(f"lib/{entry}/{name}: its name is also lib/{home[name]}/{name}")
            home[name] = entry
            sources.append((entry, name))
    elif entry not in ("vdbgi.h", "vdbgi_bench.h", "vdbgi.pc.in", "README.md"):
        bad.append(f"lib/{entry}: a file outside the stage folders")

third_party = {"openvdb/": {"shim"}, "OpenImageIO/": {"shim"}, "tiny_gltf": {"shim"},
               "embree3/": {"scene"}, "assimp/": {"scene"}}
includes = 0
for folder, name in sources:
    if name.endswith((".cpp", ".hpp")) and folder != "shim":
        bad.append(f"lib/{folder}/{name}: C++ outside shim/")
    text = open(os.path.join("lib", folder, name), encoding="utf-8").read()
    for inc in re.findall(r'^\s*#\s*include\s+"([^"]+)"', text, re.M):
        includes += 1
        if inc in ("vdbgi.h", "vdbgi_bench.h"):
            continue
        where = home.get(os.path.basename(inc))
        if where is None:
            bad.append(f"lib/{folder}/{name}: includes \"{inc}\", which lib/ does not have")
        elif where not in rows[folder]:
            bad.append(f"lib/{folder}/{name}: includes {where}/{inc}; {folder}/ may include "
                       + ", ".join(sorted(rows[folder])))
    for inc in re.findall(r'^\s*#\s*include\s+<([^>]+)>', text, re.M):
        for prefix, allowed in third_party.items():
            if inc.startswith(prefix) and folder not in allowed:
                bad.append(f"lib/{folder}/{name}: includes <{inc}>, only for " + ", ".join(sorted(allowed)))
for name in sorted(os.listdir("apps")):
    text = open(os.path.join("apps", name), encoding="utf-8").read()
    for inc in re.findall(r'^\s*#\s*include\s+"([^"]+)"', text, re.M):
        includes += 1
        if inc not in ("vdbgi.h", "vdbgi_bench.h") and not os.path.exists(os.path.join("apps", inc)):
            bad.append(f"apps/{name}: includes \"{inc}\": apps see only vdbgi.h, vdbgi_bench.h "
                       "and their own headers")
print(f"{len(sources)} files in {len(rows)} folders, {includes} includes, {len(bad)} against the rule")
for b in bad:
    print(b)
PY
