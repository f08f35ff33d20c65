#!/usr/bin/env bash
# `cmake --install` and the .deb made from this build tree: the files where
# Debian expects them, the runtime dependencies dpkg-shlibdeps found, the
# example configuration as conffiles; dpkg installs the package into a
# scratch root, and the installed ecpairctl validates a shared ENI.
#   deb_package_test.sh BUILD_DIR ENI
set -euo pipefail
build=$1
eni=$2
work=$(mktemp -d /tmp/ecpair-deb.XXXXXX)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# A staged install with prefix /usr.
staged=$work/staged
DESTDIR=$staged cmake --install "$build" --prefix /usr >"$work/install.log" 2>&1 || { cat "$work/install.log"; fail "cmake --install"; }
for path in usr/bin/ecpaird usr/bin/ecpair-linkguard usr/bin/ecpairctl etc/ecpair/controller-a.textproto lib/systemd/system/ecpaird@.service \
            usr/share/doc/ecpair/README.md; do
  [ -f "$staged/$path" ] || fail "cmake --install put no /$path"
done

(cd "$build" && cpack -G DEB -B "$work/out") >"$work/cpack.log" 2>&1 || { cat "$work/cpack.log"; fail "cpack"; }
deb=$(ls "$work"/out/ecpair_*.deb)
echo "package: $(basename "$deb") ($(du -k "$deb" | cut -f1) KiB)"

depends=$(dpkg-deb -f "$deb" Depends)
echo "Depends: $depends"
for lib in libc6 libstdc++6 libpcap0.8 libtinyxml2 libspdlog libfmt libprotobuf libboost-program-options; do
  grep -q "$lib" <<<"$depends" || fail "Depends lacks $lib"
done

contents=$(dpkg-deb -c "$deb" | awk '{print $6}')
for path in ./usr/bin/ecpaird ./usr/bin/ecpair-linkguard ./usr/bin/ecpairctl ./usr/bin/ecsim ./usr/bin/ecsim-make-eni \
            ./etc/ecpair/controller-a.textproto ./etc/ecpair/controller-b.textproto ./lib/systemd/system/ecpaird@.service \
            ./usr/share/doc/ecpair/README.md ./usr/share/doc/ecpair/docs/ARCHITECTURE.md; do
  grep -qx "$path" <<<"$contents" || fail "the package has no $path"
done
grep -q '^\./usr/local' <<<"$contents" && fail "files under /usr/local"

dpkg-deb -e "$deb" "$work/control"
for conf in controller-a controller-b; do
  grep -qx "/etc/ecpair/$conf.textproto" "$work/control/conffiles" || fail "/etc/ecpair/$conf.textproto is not a conffile"
done

# A real install into a scratch root: dpkg with its own (empty) database.
# The libraries it depends on are this machine's, so --force-depends.
root=$work/root
mkdir -p "$root/var/lib/dpkg/updates" "$root/var/lib/dpkg/info"
touch "$root/var/lib/dpkg/status"
dpkg --root="$root" --force-depends --force-not-root -i "$deb" >"$work/dpkg.log" 2>&1 || { cat "$work/dpkg.log"; fail "dpkg -i"; }
dpkg --root="$root" -s ecpair | grep -q '^Status: install ok installed' || fail "dpkg does not list ecpair as installed"
grep -q "^ExecStart=/usr/bin/ecpaird --config /etc/ecpair/%i.textproto" "$root/lib/systemd/system/ecpaird@.service" ||
  fail "the unit does not start /usr/bin/ecpaird"
grep -q "^ExecStopPost=/usr/bin/ecpair-linkguard " "$root/lib/systemd/system/ecpaird@.service" ||
  fail "the unit's ExecStopPost does not run /usr/bin/ecpair-linkguard"
grep -q "/usr/local" "$root/lib/systemd/system/ecpaird@.service" && fail "the installed unit names /usr/local"

out=$("$root/usr/bin/ecpairctl" eni "$eni") || fail "the installed ecpairctl refused $eni: $out"
# Not `echo | head`: head leaving early makes echo die of SIGPIPE, a failure under pipefail.
head -5 <<<"$out"
grep -q "slave" <<<"$out" || fail "ecpairctl eni printed no slave"
"$root/usr/bin/ecpairctl" eni "$work/control/conffiles" >/dev/null 2>&1 && fail "ecpairctl eni accepted a file that is no ENI"
echo "PASS"
