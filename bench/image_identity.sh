#!/usr/bin/env bash
# Image identity between two builds: renders every integrator on every built-in scene and on
# every Mitsuba scene in scenes/mitsuba/ at small settings with both binaries and compares the
# EXR bytes. Used to check that a refactoring changes no image.
#
#   bench/image_identity.sh [BASE_REV]            # builds BASE_REV (default HEAD~1) and the tree
#   BASE_BIN=a NEW_BIN=b bench/image_identity.sh  # compares two binaries already built
#   NEW_EXTRA="--no-auto-bandwidth" bench/image_identity.sh REV   # extra options for the new
#                                                 # binary only (a default it changed on purpose)
#   INTEGRATORS="path hybrid pcf" bench/image_identity.sh REV   # only these integrators
#   SCENES="fog-box scenes/mitsuba/x.xml" bench/image_identity.sh REV   # only these scenes
#
# Output: docs/results/image-identity/report.md (one row per render: identical / differs /
# both fail with the same message / one fails) and a non-zero exit if anything differs.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
out=${OUT:-$root/docs/results/image-identity}
work=${WORK:-$root/target/image-identity}
mkdir -p "$out" "$work"

if [ -z "${BASE_BIN:-}" ]; then
    rev=${1:-HEAD~1}
    wt=$work/base-tree
    rm -rf "$wt"
    git worktree add --detach "$wt" "$rev" >/dev/null
    (cd "$wt" && cargo build --release --bin caustica -q)
    BASE_BIN=$wt/target/release/caustica
fi
if [ -z "${NEW_BIN:-}" ]; then
    cargo build --release --bin caustica -q
    NEW_BIN=$root/target/release/caustica
fi

# shellcheck disable=SC2206 # INTEGRATORS is a list of names
integrators=(${INTEGRATORS:-path hybrid pcf lighttrace pm dpm pdm pds})
# The scenes both builds have (or the list in SCENES: built-in names and paths to XML files).
if [ -n "${SCENES:-}" ]; then
    # shellcheck disable=SC2206 # SCENES is a list of names
    scenes=($SCENES)
else
    scenes=($("$BASE_BIN" scenes))
    for f in scenes/mitsuba/*.xml; do scenes+=("$f"); done
fi

# Small settings: a few samples per pixel, few photons, one thread count (the renders are
# deterministic whatever the threads; the tests check that separately).
common=(--spp 4 --seed 7 -q)
mitsuba_defs=(-D spp=4 -D res=96 -D width=96 -D height=72)
photon_opts() {
    case $1 in
        pm | dpm) echo "--photons 20000 --global-photons 20000" ;;
        # An explicit smoothing: the scenes' own changed with the automatic choice (issue 16).
        pdm) echo "--photons 5000 --global-photons 20000 --smoothing 4" ;;
        pds) echo "--photons 5000 --global-photons 20000 --smoothing 4" ;;
        hybrid | pcf) echo "--photons 5000" ;;
        *) echo "" ;;
    esac
}

report=$out/report.md
{
    echo "# Image identity"
    echo
    echo "Base: \`$BASE_BIN\` ($("$BASE_BIN" --version 2>/dev/null || echo '?'))"
    echo "New: \`$NEW_BIN\` ${NEW_EXTRA:-}"
    echo "Settings: \`${common[*]}\`, Mitsuba scenes with those of \`${mitsuba_defs[*]}\` they declare; photon counts per"
    echo "integrator as in \`bench/image_identity.sh\`. Date: $(date -u +%F)."
    echo
    echo "| scene | integrator | result (the mean tells a real image from a black one) |"
    echo "|---|---|---|"
} >"$report"

differ=0
for s in "${scenes[@]}"; do
    name=$s
    defs=()
    case $s in
        *.xml)
            name=mitsuba/$(basename "$s" .xml)
            # Only the parameters this scene declares (-D of any other name is an error).
            for d in "${mitsuba_defs[@]}"; do
                [ "$d" = -D ] && continue
                grep -q "<default name=\"${d%%=*}\"" "$s" && defs+=(-D "$d")
            done
            ;;
    esac
    for i in "${integrators[@]}"; do
        tag="${name//\//-}-$i"
        args=(render "$s" --integrator "$i" "${common[@]}" "${defs[@]}" $(photon_opts "$i"))
        set +e
        "$BASE_BIN" "${args[@]}" -o "$work/$tag-base.exr" >"$work/$tag-base.log" 2>&1
        rb=$?
        # shellcheck disable=SC2086 # NEW_EXTRA is a list of options
        "$NEW_BIN" "${args[@]}" ${NEW_EXTRA:-} -o "$work/$tag-new.exr" >"$work/$tag-new.log" 2>&1
        rn=$?
        set -e
        if [ $rb -ne 0 ] && [ $rn -ne 0 ]; then
            if [ "$(tail -1 "$work/$tag-base.log")" = "$(tail -1 "$work/$tag-new.log")" ]; then
                result="both refuse: $(tail -1 "$work/$tag-new.log" | cut -c1-90)"
            else
                result="both refuse, messages differ: new: $(tail -1 "$work/$tag-new.log" | cut -c1-90)"
            fi
        elif [ $rb -ne 0 ] || [ $rn -ne 0 ]; then
            result="**one fails** (base $rb, new $rn)"
            differ=1
        elif cmp -s "$work/$tag-base.exr" "$work/$tag-new.exr"; then
            # The mean shows the render is not trivially black.
            mean=$("$NEW_BIN" compare "$work/$tag-new.exr" "$work/$tag-base.exr" |
                awk '/^mean image/ {print $4}')
            result="identical (mean R $mean W/m²/sr)"
        else
            result="**differs**"
            differ=1
        fi
        echo "| $name | $i | $result |" >>"$report"
        echo "$name $i: $result"
    done
done
echo >>"$report"
if [ $differ -eq 0 ]; then
    echo "All renders identical (or refused identically) to the byte." >>"$report"
fi
echo "report: $report"
exit $differ
