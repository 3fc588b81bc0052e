#!/usr/bin/env bash
# Prints the path of a libLLVM.so.19.1 for Dr.Jit's LLVM backend (Mitsuba 3's llvm_* variants),
# downloading Debian's libllvm19 package and unpacking it (dpkg -x, no root install) into a
# cache directory next to the peers venv if it is not there yet. Use it as
#   DRJIT_LIBLLVM_PATH=$(bash tools/peers/libllvm.sh)
# The system's LLVM 14/15 makes Dr.Jit 1.5 abort; bookworm/main carries libllvm19
# (1:19.1.7-3~deb12u1). Its run-time dependencies (libedit2, libffi8, libxml2, libz3-4,
# libzstd1, zlib1g) must be installed; the script checks with ldd. Override the location with
# CAUSTICA_LIBLLVM_DIR.
set -euo pipefail
dir="${CAUSTICA_LIBLLVM_DIR:-$HOME/.cache/caustica/libllvm19}"
lib="$dir/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1"
if [ ! -f "$lib" ]; then
  mkdir -p "$dir/deb"
  (cd "$dir/deb" && rm -f libllvm19_*.deb && apt-get download -q libllvm19 >&2)
  deb=$(ls "$dir"/deb/libllvm19_*.deb)
  # unpack into a temporary directory first so an interrupted run leaves no half library
  tmp=$(mktemp -d "$dir/unpack.XXXXXX")
  dpkg -x "$deb" "$tmp"
  if [ ! -f "$tmp/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1" ]; then
    echo "libllvm.sh: $deb holds no usr/lib/x86_64-linux-gnu/libLLVM.so.19.1:" >&2
    dpkg-deb -c "$deb" | grep -i 'libLLVM' >&2 || true
    exit 1
  fi
  rm -rf "$dir/usr"
  mv "$tmp/usr" "$dir/usr"
  rmdir "$tmp" 2>/dev/null || rm -rf "$tmp"
  dpkg-deb -f "$deb" Version > "$dir/VERSION"
fi
if missing=$(ldd "$lib" | grep 'not found'); then
  echo "libllvm.sh: $lib needs libraries that are not installed:" >&2
  echo "$missing" >&2
  exit 1
fi
echo "$lib"
