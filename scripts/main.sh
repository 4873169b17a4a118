#!/usr/bin/env bash
# The main job: set everything up, then compute the coarse SDF of the bundled
# sample mesh and write the .vdb, a PNG slice through it and the figures.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${RTSDF_BUILD_DIR:-$root/build}"
out="${RTSDF_OUT:-$root/out}"
"$root/scripts/setup.sh"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"

mkdir -p "$out"
mesh="$build/samples/cad_part_110k.ply"
echo "== rtsdf sdf $mesh"
"$build/native/rtsdf" sdf "$mesh" --coarse-res 128 --beta 0.5 --out "$out/cad_part.vdb" --json "$out/cad_part.json"
/usr/bin/python3 "$root/scripts/sdf_slice.py" "$out/cad_part.vdb" --grid coarse --out "$out/cad_part_slice.png"
/usr/bin/python3 - "$out/cad_part.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
ms = r["ms"]
print(f"device {r['device']}; {r['triangles']} triangles; grid {'x'.join(map(str, r['dims']))} "
      f"voxels of {r['voxel_size']:.5f}; beta {r['beta']:.5f}")
print(f"voxelize {ms['voxelize']:.1f} ms, jump flood {ms['jump_flood']:.1f} ms "
      f"({len(ms['jump_flood_passes'])} passes), SDF total {ms['total']:.1f} ms, whole run {ms['process']:.1f} ms")
PY
echo "== wrote $out/cad_part.vdb, $out/cad_part_slice.png, $out/cad_part.json"
