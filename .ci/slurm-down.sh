#!/usr/bin/env bash
# Stop the single-node Slurm cluster started by .ci/slurm-up.sh: slurmd, slurmctld, then
# munged, each by its pid file in $GRANFLOW_SLURM_DIR (default /tmp/granflow-slurm); never
# by process name.
set -uo pipefail

S="${GRANFLOW_SLURM_DIR:-/tmp/granflow-slurm}"

stop_by_pidfile() {
    local name="$1" file="$2" pid
    [ -f "$file" ] || return 0
    pid="$(cat "$file" 2>/dev/null || true)"
    if [ -n "$pid" ] && kill -0 "$pid" 2>/dev/null; then
        kill "$pid" 2>/dev/null || true
        for _ in $(seq 1 50); do
            kill -0 "$pid" 2>/dev/null || break
            sleep 0.2
        done
        if kill -0 "$pid" 2>/dev/null; then
            echo "slurm-down: $name (pid $pid) did not stop on TERM; sending KILL" >&2
            kill -9 "$pid" 2>/dev/null || true
        fi
    fi
    rm -f "$file"
}

stop_by_pidfile slurmd "$S/run/slurmd.pid"
stop_by_pidfile slurmctld "$S/run/slurmctld.pid"
stop_by_pidfile munged "$S/run/munge/munged.pid"
exit 0
