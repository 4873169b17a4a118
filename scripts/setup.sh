#!/usr/bin/env bash
# Sets up everything on Debian 12 as root: system packages, the build, and the
# Blender add-on with its native module. Safe to run again.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${RTSDF_BUILD_DIR:-$root/build}"

mapfile -t packages < <(grep -v '^\s*#' "$root/scripts/debian-packages.txt" | sed '/^\s*$/d')
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "== installing ${#missing[@]} Debian packages: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -q
  apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

echo "== building in $build"
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DPython3_EXECUTABLE=/usr/bin/python3 >/dev/null
cmake --build "$build" -j "$(nproc)"

# Blender's user add-ons folder (Blender picks its own version's path).
addons="$(blender -b --factory-startup --python-expr \
  "import bpy; print('RTSDF_ADDONS=' + bpy.utils.user_resource('SCRIPTS', path='addons', create=True))" 2>/dev/null |
  sed -n 's/^RTSDF_ADDONS=//p')"
if [[ -z "$addons" ]]; then
  echo "setup: could not ask Blender for its add-ons folder" >&2
  exit 1
fi
echo "== installing the add-on into $addons/rtsdf"
rm -rf "$addons/rtsdf"
cp -r "$build/blender_user_scripts/addons/rtsdf" "$addons/rtsdf"
echo "== setup done"
