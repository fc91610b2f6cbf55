#!/bin/sh
# Phong + shadows decided by shadow rays (options.shadow.method rays) and by shadow maps, each beside
# Embree casting a primary ray and one exact shadow ray per lamp within reach, on the Sweet Home 3D
# homes with their own sun and lamps: ../shared/peers/tools/side_by_side.py --homes --home-lights,
# mode lights+shadows (1280x720, interleaved rounds, ratios ours / Embree). side_by_side.py passes no
# flag of ours, so a wrapper adds --shadow-method to each bench-render it runs. The load is printed by
# side_by_side.py before each run: quote it with the numbers.
#   bench/shadow_rays_peers.sh BUILD_DIR [side_by_side.py options, e.g. --scenes 3BedroomApartment --rounds 2]
# Writes bench/results/shadow_rays_peers_{map,rays}$SUFFIX.json. PEERS_BUILD defaults to /work/peers/build.
# A later --modes replaces lights+shadows: SUFFIX=_conference ... --scenes conference --modes vs-embree
# draws the conference room with its sun. The homes always get their lamps here (--home-lights); for a
# home with one sun, run side_by_side.py --homes --modes vs-embree with the same wrapper.
# Threads: side_by_side.py gives Embree no --threads flag, so it uses every core whatever --threads says.
set -eu
build=${1:?usage: bench/shadow_rays_peers.sh BUILD_DIR [side_by_side.py options]}
shift
here=$(cd "$(dirname "$0")" && pwd)
binary=$(cd "$build" && pwd)/roomrender
peers=${PEERS:-$here/../../shared/peers}
[ -d "$peers" ] || peers=/work/shared/peers
export PEERS_BUILD=${PEERS_BUILD:-/work/peers/build}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$here/results"
for method in map rays; do
  wrapper=$tmp/roomrender-$method
  cat >"$wrapper" <<WRAP
#!/bin/sh
if [ "\$1" = bench-render ]; then shift; exec "$binary" bench-render "\$@" --shadow-method $method; fi
exec "$binary" "\$@"
WRAP
  chmod +x "$wrapper"
  echo "== shadow.method $method"
  python3 "$peers/tools/side_by_side.py" "$wrapper" --homes --home-lights --modes lights+shadows \
    --json "$here/results/shadow_rays_peers_$method${SUFFIX:-}.json" "$@"
done
