#!/usr/bin/env bash
# Packs the native tests and the SDF benchmarks of a build (scripts/setup.sh)
# for a Linux x86-64 machine with a Vulkan GPU but without Debian 12's
# packages: OUT/bundle.tar.xz holds the binaries, every shared library they
# load but the C library's, the Vulkan loader, glvnd (which NVIDIA's Vulkan
# driver loads), the Khronos validation layer and the meshes the tests read;
# OUT/run.sh unpacks it there and runs the tests with validation on (a
# validation message fails a test), then the fine, scaling and coarse
# benchmarks, writing their logs to $OUT (default: the current directory).
#
#   scripts/portable_tests.sh OUT        (here, after scripts/setup.sh)
#   bash OUT/run.sh                      (there, from the folder holding OUT; as root: the
#                                         test binary reads its meshes from this build's paths)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${RTSDF_BUILD_DIR:-$root/build}"
out="${1:?usage: scripts/portable_tests.sh OUT_DIR}"
models=/usr/share/assimp/models
lib=/usr/lib/x86_64-linux-gnu
stage="$(mktemp -d)/rtsdf_portable"
mkdir -p "$stage"/{bin,lib,layer,samples} "$out"
cp "$build"/tests/rtsdf_native_tests "$build"/bench/rtsdf_bench_{fine,scaling,coarse} "$build"/native/rtsdf "$stage/bin/"
for binary in "$stage"/bin/*; do ldd "$binary" | awk '$3 ~ /^\// {print $3}'; done | sort -u |
  grep -v -E '/(libc|libm|ld-linux-x86-64|libpthread|libdl|librt)\.so' | xargs -I{} cp -L {} "$stage/lib/"
cp -L "$lib"/{libvulkan.so.1,libGLdispatch.so.0,libGLX.so.0,libEGL.so.1,libGL.so.1,libOpenGL.so.0} "$stage/lib/"
cp "$lib/libVkLayer_khronos_validation.so" "$stage/layer/"
sed 's#"library_path": *"[^"]*"#"library_path": "./libVkLayer_khronos_validation.so"#' \
  /usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json > "$stage/layer/VkLayer_khronos_validation.json"
cp "$build"/samples/cad_part_{10k,20k,110k}.ply "$stage/samples/"
# (the scaling benchmark's million triangles, where the build made them: target rtsdf_bench_meshes)
[ -f "$build/samples/cad_part_1m.ply" ] && cp "$build/samples/cad_part_1m.ply" "$stage/samples/"
# (the third-party models the tests and the fine benchmark read, where Debian's assimp-testmodels has them)
for model in OBJ/spider.obj glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb; do
  [ -f "$models/$model" ] && mkdir -p "$stage/models/$(dirname "$model")" && cp "$models/$model" "$stage/models/$model"
done
tar -C "$(dirname "$stage")" -cf - rtsdf_portable | xz -9 -T0 > "$out/bundle.tar.xz"
rm -rf "$(dirname "$stage")"

cat > "$out/run.sh" <<EOF
#!/usr/bin/env bash
# Made by scripts/portable_tests.sh from $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo "a build").
here="\$(cd "\$(dirname "\${BASH_SOURCE[0]}")" && pwd)"
logs="\${OUT:-\$PWD}"
tar -C /tmp -xJf "\$here/bundle.tar.xz"
B=/tmp/rtsdf_portable
mkdir -p "$build/samples" "$build/native" "$models" && cp "\$B"/samples/*.ply "$build/samples/"
cp "\$B/bin/rtsdf" "$build/native/"  # (the coarse benchmark times the command)
[ -d "\$B/models" ] && cp -r "\$B"/models/* "$models/"
export LD_LIBRARY_PATH="\$B/lib" VK_LAYER_PATH="\$B/layer" XDG_RUNTIME_DIR=/tmp
# NVIDIA's driver manifest where a container mounts it (else the loader's own search)
icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
[ -f "\$icd" ] && export VK_DRIVER_FILES="\$icd" VK_ICD_FILENAMES="\$icd"
cd "\$B/bin"
RTSDF_VALIDATION=1 timeout 600 ./rtsdf_native_tests > "\$logs/tests.log" 2>&1; echo "native tests: exit \$?"
grep -E '^\[  (PASSED|FAILED|SKIPPED) ' "\$logs/tests.log"
echo "validation messages: \$(grep -c -i 'validation' "\$logs/tests.log")"
timeout 120 ./rtsdf_bench_fine --quick --frames 3 2>&1 | tee "\$logs/bench_fine.log"
[ -f "$models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb" ] &&
  timeout 120 ./rtsdf_bench_fine --quick --frames 3 --mesh "$models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb" 2>&1 | tee "\$logs/bench_fine_engine.log"
timeout 120 ./rtsdf_bench_scaling 2>&1 | tee "\$logs/bench_scaling.log"
timeout 120 ./rtsdf_bench_coarse 2>&1 | tee "\$logs/bench_coarse.log"
EOF
chmod +x "$out/run.sh"
echo "wrote $out/bundle.tar.xz ($(du -h "$out/bundle.tar.xz" | cut -f1)) and $out/run.sh"
