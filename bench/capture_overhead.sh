#!/usr/bin/env bash
# mesocap's per-shot overhead over the camera's own capture+download time (issue 3: < 50 ms),
# measured with libgphoto2's virtual camera serving a full-size JPEG.
#
#   bench/capture_overhead.sh [BUILD_DIR] [SHOTS]      (defaults: build, 20)
#
# Builds the virtual camera (scripts/build-vusb.sh), compiles a second copy of it that serves a
# 6000x4000 JPEG (~19 MB, like a 24 MP body's), runs `mesocap capture` against it and prints the
# report's timing line: camera = capture + download inside libgphoto2; overhead = mesocap's
# checks, fsyncs, rename, EXIF read-back and journal append.
set -euo pipefail
repo="$(cd "$(dirname "$0")/.." && pwd)"
build="$(cd "${1:-$repo/build}" && pwd)"
shots="${2:-20}"
mesocap="$build/app/mesocap"
[[ -x "$mesocap" ]] || { echo "capture_overhead: $mesocap not built" >&2; exit 1; }
"$mesocap" capture --help >/dev/null 2>&1 || { echo "capture_overhead: this mesocap has no capture command" >&2; exit 1; }

cache="$build/vusb"
bash "$repo/scripts/build-vusb.sh" "$cache" >/dev/null
big="$cache/bench"
if [[ ! -f "$big/iolibs/vusb.so" ]]; then
  mkdir -p "$big/vcamera/DCIM/100TEST" "$big/iolibs"
  oiiotool --pattern noise:type=gaussian:mean=0.5:stddev=0.05 6000x4000 3 \
    --attrib:type=int Exif:Flash 1 -d uint8 -o:quality=85 "$big/vcamera/DCIM/100TEST/DSC_0001.jpg"
  # shellcheck disable=SC2046
  gcc -shared -fPIC -O1 -w -D_GPHOTO2_INTERNAL_CODE -I"$cache/work" -DVCAMERADIR="\"$big/vcamera\"" \
    -o "$big/iolibs/vusb.so" "$cache/work/vusb.c" "$cache/work/vcamera.c" \
    $(pkg-config --cflags --libs libgphoto2_port libexif)
fi

out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
echo "served file: $(stat -c %s "$big/vcamera/DCIM/100TEST/DSC_0001.jpg") bytes; session on $(df --output=source "$out" | tail -1)"
# The virtual camera prints a harmless "001,001: No such file or directory" when opened.
IOLIBS="$big/iolibs" "$mesocap" capture --out "$out/session" --shots "$shots" --no-progress 2> >(grep -v '^001,001' >&2)
