#!/usr/bin/env bash
# Builds resynth_fill, a benchmark-only peer: the Resynthesizer engine (Harrison's per-pixel texture
# synthesis, GIMP's Resynthesizer plug-in, GPL-3.0-or-later) compiled from its upstream source with
# our small driver resynth_fill.c. The engine's source is fetched into a cache directory outside
# the repository's sources at build time and is never copied into the repository.
#
#   bash bench/resynth_peer/build.sh [CACHE_DIR=build/peer/resynth]
#
# Source of the engine, in this order:
#   RESYNTH_SRC=DIR  a resynthesizer 2.0.x tree (DIR/lib/engine.c) or its lib/ directory, e.g. a
#                    checkout of bootchk/resynthesizer at tag v2.0.3;
#   otherwise        Debian's source package gimp-plugin-registry (which carries resynthesizer
#                    2.0.3), fetched by scripts/debian-source.sh; the version is the source
#                    version of the archive's gimp-plugin-registry binary package, or
#                    RESYNTH_DEBIAN_VERSION.
# The engine files are copied into CACHE_DIR/engine and adapted there, not in the fetched tree:
#   - buildSwitches.h is wrapped to select the upstream's own "config 3" (the GLib-free engine on
#     glibProxy, POSIX threads; GLib's GMutex calls are mapped onto pthread mutexes), keeping the
#     upstream's threading (THREAD_LIMIT 8 threads, as in GIMP), or one thread for the serial build;
#   - engine.c gets two one-line edits: its fixed PRNG seed (1198472) becomes resynth_peer_seed (the
#     driver's --seed, default 1198472), and a call resynth_peer_sources(&sourceOfMap) is added after
#     refinement so that the driver can write the source coordinates of each synthesized pixel.
# Builds CACHE_DIR/resynth_fill (the upstream's threading: 8 threads, so its output varies from run
# to run even with --seed) and CACHE_DIR/resynth_fill_serial (one thread: reproducible with --seed).
# Prints the path of the threaded executable. Needs gcc and libpng-dev (and dpkg-dev for the Debian route).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
cache="${1:-$repo/build/peer/resynth}"
mkdir -p "$cache"
cache="$(cd "$cache" && pwd)"
log() { echo "resynth_peer: $*" >&2; }
die() { log "error: $*"; exit 1; }

command -v gcc >/dev/null || die "gcc is missing"
[[ -f /usr/include/png.h ]] || die "libpng-dev is missing (apt-get install libpng-dev)"

if [[ -n ${RESYNTH_SRC:-} ]]; then
  src="$(cd "$RESYNTH_SRC" && pwd)"
  origin="RESYNTH_SRC=$src"
else
  version="${RESYNTH_DEBIAN_VERSION:-}"
  if [[ -z $version ]]; then
    version="$(apt-cache show gimp-plugin-registry 2>/dev/null |
      sed -n 's/^Source: gimp-plugin-registry (\(.*\))$/\1/p' | head -n1)"
    [[ -n $version ]] || version="$(apt-cache show gimp-plugin-registry 2>/dev/null |
      sed -n 's/^Version: //p' | head -n1)"
    [[ -n $version ]] || die "gimp-plugin-registry is not in the apt lists (apt-get update), or set RESYNTH_DEBIAN_VERSION / RESYNTH_SRC"
  fi
  src="$(bash "$repo/scripts/debian-source.sh" gimp-plugin-registry "$version" "$cache/debian")" ||
    die "could not fetch Debian's gimp-plugin-registry $version source; set RESYNTH_SRC to a resynthesizer 2.0.x tree"
  origin="Debian source gimp-plugin-registry $version"
fi
# The engine: lib/ of a resynthesizer 2.0.x tree (in the Debian tree, under its resynthesizer dir).
if [[ -f $src/engine.c && -f $src/imageSynth.c ]]; then
  lib="$src"
else
  lib="$(find "$src" -path '*/lib/engine.c' -print 2>/dev/null | while read -r f; do
    d="$(dirname "$f")"; [[ -f $d/imageSynth.c && -f $d/glibProxy.c ]] && { echo "$d"; break; }; done)"
fi
[[ -n ${lib:-} && -f $lib/engine.c ]] || die "no resynthesizer lib/engine.c (with imageSynth.c, glibProxy.c) under $src"
[[ -f $lib/buildSwitches.h ]] || die "$lib has no buildSwitches.h: only the resynthesizer 2.0.x layout is supported"
log "engine from $origin: $lib"

engine="$cache/engine"
rm -rf "$engine"
mkdir -p "$engine"
cp "$lib"/*.c "$lib"/*.h "$engine/"
[[ -f $lib/../COPYING ]] && cp "$lib/../COPYING" "$engine/COPYING.resynthesizer"
mv "$engine/buildSwitches.h" "$engine/buildSwitches.upstream.h"
cat >"$engine/buildSwitches.h" <<'EOF'
/* Written by mesocap's bench/resynth_peer/build.sh: the upstream switches, then its "config 3"
   (engine on glibProxy, no GLib/GIMP), threaded on POSIX threads. */
#include "buildSwitches.upstream.h"
#undef SYNTH_USE_GLIB
#undef SYNTH_USE_GLIB_THREADS
#ifndef USE_GLIB_PROXY
#define USE_GLIB_PROXY TRUE
#endif
#include <pthread.h>
typedef pthread_mutex_t GMutex;
#ifdef RESYNTH_PEER_SERIAL /* one thread: with --seed, the output is reproducible */
#undef SYNTH_THREADED
#undef THREAD_LIMIT
#define THREAD_LIMIT 1
#else
#define g_mutex_init(m) pthread_mutex_init((m), NULL)
#define g_mutex_lock(m) pthread_mutex_lock(m)
#define g_mutex_unlock(m) pthread_mutex_unlock(m)
#endif
EOF
grep -q 'g_rand_new_with_seed(1198472)' "$engine/engine.c" || die "engine.c: the seed line was not found"
[[ $(grep -c '^  free_map(&recentProberMap);' "$engine/engine.c") == 1 ]] ||
  die "engine.c: the line after refinement was not found"
sed -i -e 's/g_rand_new_with_seed(1198472)/g_rand_new_with_seed(resynth_peer_seed)/' \
  -e 's/^  free_map(&recentProberMap);/  resynth_peer_sources(\&sourceOfMap);\n&/' "$engine/engine.c"
cat >"$engine/resynth_peer_hooks.h" <<'EOF'
/* Written by mesocap's bench/resynth_peer/build.sh; defined in resynth_fill.c. */
extern unsigned int resynth_peer_seed;
void resynth_peer_sources(const void *source_of_map);
EOF

cflags=(-O3 -std=gnu99 -fno-common -ffast-math -w -I"$engine")
gcc -O2 -std=gnu99 -Wall -I"$engine" -include stddef.h -c "$here/resynth_fill.c" -o "$engine/resynth_fill.o"
# resynth_fill: threaded as in GIMP; resynth_fill_serial: one thread, reproducible for a given --seed.
for variant in resynth_fill resynth_fill_serial; do
  defs=()
  [[ $variant == resynth_fill_serial ]] && defs=(-DRESYNTH_PEER_SERIAL)
  objs=()
  for f in imageSynth engine glibProxy engineParams imageFormat progress; do
    extra=()
    [[ $f == engine ]] && extra=(-include "$engine/resynth_peer_hooks.h")
    # progress.c includes glibProxy.h only in the GLib configurations; it needs it in config 3 too.
    [[ $f == progress ]] && ! grep -q glibProxy.h "$engine/progress.c" && extra=(-include "$engine/glibProxy.h")
    gcc "${cflags[@]}" "${defs[@]}" "${extra[@]}" -c "$engine/$f.c" -o "$engine/$f.$variant.o"
    objs+=("$engine/$f.$variant.o")
  done
  gcc -o "$cache/$variant" "$engine/resynth_fill.o" "${objs[@]}" -lpng -lm -lpthread
done
log "built $cache/resynth_fill (threaded, as in GIMP) and $cache/resynth_fill_serial (one thread)"
echo "$cache/resynth_fill"
