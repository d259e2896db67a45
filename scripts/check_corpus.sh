#!/bin/sh
# Verify the corpus against LinuxCNC's rs274: every good program runs to completion (exit 0,
# nothing on stderr but rs274's "executing" banner), every bad program is rejected (exit != 0).
set -u
cd "$(dirname "$0")/../tests/corpus" || exit 2
fail=0
for f in *.ngc; do
    # oword_lib_* programs call subroutine files: rs274 finds them through the INI's
    # SUBROUTINE_PATH, as the differential test runs them.
    ini=""
    # ini_* programs read ini/settings.ini (ORIENT_OFFSET, #<_ini[...]...> values).
    case "$f" in oword_lib_*) ini="-i oword_lib/paths.ini" ;; ini_*) ini="-i ini/settings.ini" ;; esac
    # var_* programs start from a copy of var/start.var (rs274 -v writes the file back).
    case "$f" in var_*) tmpvar=$(mktemp); cp var/start.var "$tmpvar"; ini="-v $tmpvar" ;; esac
    # shellcheck disable=SC2086
    err=$(rs274 $ini -g -t tool.tbl "$f" 2>&1 >/dev/null)
    rc=$?
    case "$f" in var_*) rm -f "$tmpvar" "$tmpvar.bak" ;; esac
    extra=$(printf '%s\n' "$err" | grep -v '^executing$' | grep -v '^$')
    if [ $rc -ne 0 ] || [ -n "$extra" ]; then
        echo "GOOD FAILS: $f (exit $rc): $extra"
        fail=1
    fi
done
for f in bad/*.ngc; do
    ini=""
    case "$f" in bad/ini_*) ini="-i ini/settings.ini" ;; esac
    # shellcheck disable=SC2086
    if rs274 $ini -g -t tool.tbl "$f" >/dev/null 2>&1; then
        echo "BAD ACCEPTED: $f"
        fail=1
    fi
done
echo "good: $(ls *.ngc | wc -l)  bad: $(ls bad/*.ngc | wc -l)"
exit $fail
