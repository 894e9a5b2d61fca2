#!/usr/bin/env bash
# Builds libgphoto2's virtual USB camera (a Nikon D750 over PTP, libgphoto2_port/vusb in the
# Debian source package) as a port library, so the real libgphoto2 capture path can be tested
# without a camera.
#
#   bash scripts/build-vusb.sh [CACHE_DIR]      (default: build/vusb)
#
# Leaves in CACHE_DIR:
#   iolibs/vusb.so          run mesocap with IOLIBS=CACHE_DIR/iolibs (that folder holds only it)
#   vcamera/DCIM/100TEST/   the photos the camera serves; a capture duplicates the first JPEG
# and prints CACHE_DIR/iolibs on stdout. Idempotent: a second run only checks the cache.
#
# The source comes from `apt-get source libgphoto2` (the installed version) through
# scripts/debian-source.sh, on a private apt state: the machine's apt configuration is not changed.
# Known facts about 2.5.30 (issue 3): vcamera.h must say `#define FUZZ_PTP 1` instead of
# `#undef FUZZ_PTP` or the port never matches a camera; the .c files are compiled beside the
# patched header; -DVCAMERADIR must name a folder with DCIM/<folder>/*.jpg (without one the
# camera crashes); after 26 captures in one process it reports the card full.
set -euo pipefail

repo="$(cd "$(dirname "$0")/.." && pwd)"
cache="${1:-$repo/build/vusb}"
mkdir -p "$cache"
cache="$(cd "$cache" && pwd)"
log() { echo "build-vusb: $*" >&2; }
die() { log "error: $*"; exit 1; }

iolibs="$cache/iolibs"
photos="$cache/vcamera"
stamp="$cache/.built-from"
version="$(dpkg-query -W -f='${Version}' libgphoto2-6 2>/dev/null || true)"
[[ -n "$version" ]] || die "libgphoto2-6 is not installed (bash scripts/install-deps.sh)"
# Rebuilt when this script or the installed libgphoto2 changes.
script_sum="$(sha256sum "$0" | cut -d' ' -f1) libgphoto2=$version"

if [[ -f "$iolibs/vusb.so" && -f "$stamp" && "$(cat "$stamp")" == "$script_sum" ]] &&
   compgen -G "$photos/DCIM/100TEST/*.jpg" >/dev/null; then
  echo "$iolibs"
  exit 0
fi

for tool in gcc pkg-config; do
  command -v "$tool" >/dev/null || die "$tool is missing (bash scripts/install-deps.sh)"
done
pkg-config --exists libgphoto2_port libexif || die "libgphoto2-dev / libexif-dev missing (bash scripts/install-deps.sh)"

# 1. The source of the installed libgphoto2.
upstream="${version%%-*}"
src="$cache/src/libgphoto2-$upstream"
if [[ ! -f "$src/libgphoto2_port/vusb/vcamera.c" ]]; then
  log "fetching libgphoto2 $version source"
  bash "$repo/scripts/debian-source.sh" libgphoto2 "$version" "$cache/src" >/dev/null ||
    die "could not fetch the libgphoto2 $version source"
  [[ -f "$src/libgphoto2_port/vusb/vcamera.c" ]] || die "$src/libgphoto2_port/vusb/vcamera.c not found in the source"
fi

# 2. The photos the camera serves: a small JPEG with the EXIF a flash shot carries.
if ! compgen -G "$photos/DCIM/100TEST/*.jpg" >/dev/null; then
  command -v oiiotool >/dev/null || die "oiiotool is missing (openimageio-tools; bash scripts/install-deps.sh)"
  mkdir -p "$photos/DCIM/100TEST"
  oiiotool --pattern checker:width=16:height=16:color1=0.8,0.6,0.3:color2=0.1,0.2,0.4 320x240 3 \
    --attrib Make "Nikon" --attrib Model "vusb D750" \
    --attrib:type=float ExposureTime 0.008 --attrib:type=float FNumber 8 \
    --attrib:type=int Exif:PhotographicSensitivity 200 --attrib:type=int Exif:Flash 1 \
    --attrib Exif:DateTimeOriginal "2026:01:01 12:00:00" \
    -d uint8 -o "$photos/DCIM/100TEST/DSC_0001.jpg"
fi

# 3. Patch and build, beside a copy of the sources.
work="$cache/work"
rm -rf "$work"
mkdir -p "$work/libgphoto2_port" "$work/gphoto2" "$iolibs"
cp "$src/libgphoto2_port/vusb/"{vusb.c,vcamera.c,vcamera.h} "$work/"
cp "$src/libgphoto2_port/libgphoto2_port/i18n.h" "$work/libgphoto2_port/"
# The port-library interface is not installed by libgphoto2-dev; the rest comes from the system.
cp "$src/libgphoto2_port/gphoto2/gphoto2-port-library.h" "$work/gphoto2/"
sed -i 's/^#undef FUZZ_PTP$/#define FUZZ_PTP 1/' "$work/vcamera.h"
grep -q '^#define FUZZ_PTP 1$' "$work/vcamera.h" || die "could not patch FUZZ_PTP in vcamera.h"
cat >"$work/config.h" <<'EOF'
/* Minimal config.h for building the virtual camera outside libgphoto2's autotools tree. */
#define HAVE_LIBEXIF 1
#define HAVE_SYS_PARAM_H 1
#include <time.h>
#define GETTEXT_PACKAGE_LIBGPHOTO2_PORT "libgphoto2_port-12"
EOF
# shellcheck disable=SC2046
gcc -shared -fPIC -O1 -w -D_GPHOTO2_INTERNAL_CODE -I"$work" -DVCAMERADIR="\"$photos\"" -o "$iolibs/vusb.so.tmp" \
  "$work/vusb.c" "$work/vcamera.c" $(pkg-config --cflags --libs libgphoto2_port libexif) ||
  die "compiling vusb.so failed"
mv "$iolibs/vusb.so.tmp" "$iolibs/vusb.so"
echo "$script_sum" >"$stamp"
log "built $iolibs/vusb.so serving $photos"
echo "$iolibs"
