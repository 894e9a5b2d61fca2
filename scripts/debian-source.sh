#!/usr/bin/env bash
# Fetches and unpacks the Debian source of an installed package, without touching the machine's
# apt configuration: apt runs on a private state (sources, lists, cache) under DEST/.apt, whose
# deb-src entries are derived from the machine's own deb entries.
#
#   bash scripts/debian-source.sh SOURCE_PACKAGE VERSION DEST
#
# Leaves the unpacked tree in DEST/<package>-<upstream version>/ and prints its path. Needs
# network access to the Debian archive the machine already uses, and dpkg-dev (dpkg-source).
# Any user can run it: nothing outside DEST is written.
set -euo pipefail

package=${1:?usage: debian-source.sh SOURCE_PACKAGE VERSION DEST}
version=${2:?usage: debian-source.sh SOURCE_PACKAGE VERSION DEST}
dest=${3:?usage: debian-source.sh SOURCE_PACKAGE VERSION DEST}
log() { echo "debian-source: $*" >&2; }
die() { log "error: $*"; exit 1; }

command -v dpkg-source >/dev/null || die "dpkg-dev is missing (bash scripts/install-deps.sh)"
mkdir -p "$dest"
dest=$(cd "$dest" && pwd)
upstream=${version#*:}
upstream=${upstream%-*}
tree=$dest/$package-$upstream
if [[ -d $tree ]]; then
  echo "$tree"
  exit 0
fi

state=$dest/.apt
mkdir -p "$state/sources.list.d" "$state/lists/partial" "$state/cache/archives/partial"
: >"$state/sources.list"
# deb-src twins of the machine's deb entries (deb822 .sources files and one-line .list files).
for sources in /etc/apt/sources.list.d/*.sources; do
  [[ -f $sources ]] || continue
  grep -Eq '^Types:(.* )?deb( |$)' "$sources" || continue
  sed -e 's/^Types:.*$/Types: deb-src/' "$sources" >"$state/sources.list.d/$(basename "$sources")"
done
for list in /etc/apt/sources.list /etc/apt/sources.list.d/*.list; do
  [[ -f $list ]] || continue
  grep '^deb ' "$list" | sed 's/^deb /deb-src /' >>"$state/sources.list" || true
done
[[ -s $state/sources.list ]] || compgen -G "$state/sources.list.d/*.sources" >/dev/null ||
  die "no apt deb entries found to derive deb-src entries from"

apt_private=(-o "Dir::Etc::SourceList=$state/sources.list" -o "Dir::Etc::SourceParts=$state/sources.list.d"
  -o "Dir::State::Lists=$state/lists" -o "Dir::Cache=$state/cache" -o "Dir::Cache::pkgcache="
  -o "Dir::Cache::srcpkgcache=" -o "APT::Sandbox::User=$(id -un)" -o "Debug::NoLocking=1")
log "reading the Debian source index (private apt state in $state)"
apt-get "${apt_private[@]}" -q update >"$state/update.log" 2>&1 ||
  die "apt-get update on the private state failed (see $state/update.log)"
log "fetching $package $version"
(cd "$dest" && apt-get "${apt_private[@]}" -q source "$package=$version" >"$state/source.log" 2>&1) ||
  die "apt-get source $package=$version failed (see $state/source.log)"
[[ -d $tree ]] || die "$tree not found after unpacking (see $state/source.log)"
echo "$tree"
