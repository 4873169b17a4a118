#!/usr/bin/env bash
# The main job: set everything up, then
# 1. compute the SDFs of the bundled sample mesh: .vdb, a PNG slice, figures;
# 2. render the bundled sample scene with RTSDF and with Cycles and write them
#    side by side with the figures (RMSE, SSIM, shadow-region RMSE, time ratio).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${RTSDF_BUILD_DIR:-$root/build}"
out="${RTSDF_OUT:-$root/out}"
"$root/scripts/setup.sh"
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"

mkdir -p "$out"
mesh="$build/samples/cad_part_110k.ply"
echo "== rtsdf sdf $mesh"
"$build/native/rtsdf" sdf "$mesh" --coarse-res 64 --fine-res 128 --frames 32 --out "$out/cad_part.vdb" --json "$out/cad_part.json"
/usr/bin/python3 "$root/scripts/sdf_slice.py" "$out/cad_part.vdb" --grid fine --out "$out/cad_part_slice.png"
/usr/bin/python3 - "$out/cad_part.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
ms = r["ms"]
print(f"device {r['device']}; {r['triangles']} triangles; grid {'x'.join(map(str, r['dims']))} "
      f"voxels of {r['voxel_size']:.5f}; beta {r['beta']:.5f}")
print(f"coarse: voxelize {ms['voxelize']:.1f} ms, jump flood {ms['jump_flood']:.1f} ms "
      f"({len(ms['jump_flood_passes'])} passes), build {ms['total']:.1f} ms")
print(f"fine: {'x'.join(map(str, r['fine_dims']))}, {r['texels_traced']} texels and {r['rays_per_frame']} rays "
      f"per frame, {ms['fine_trace']:.1f} ms per frame (interleave {r['interleave']}), BVH {ms['bvh_build']:.1f} ms; "
      f"whole run {ms['process']:.0f} ms")
PY
echo "== wrote $out/cad_part.vdb, $out/cad_part_slice.png, $out/cad_part.json"

echo "== rendering $build/samples/sphere_plane.blend with RTSDF and Cycles"
/usr/bin/python3 "$root/scripts/compare_render.py" "$build/samples/sphere_plane.blend" --out "$out" --cycles-samples 256
echo "== wrote $out/sphere_plane_compare.png, $out/sphere_plane_figures.json"
