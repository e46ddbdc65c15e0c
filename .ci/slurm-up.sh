#!/usr/bin/env bash
# Start a single-node Slurm cluster on loopback for the integration tests (see
# shared/spec/slurm.md): install Debian's slurm-wlm + munge if missing, write a minimal
# slurm.conf (no cgroups, no accounting), start munged, slurmctld and slurmd, and wait until
# the node is idle. State, pid and log files live in $GRANFLOW_SLURM_DIR (default
# /tmp/granflow-slurm); .ci/slurm-down.sh stops the daemons by their pid files.
# Needs root (CI and the development machines run as root).
set -euo pipefail

S="${GRANFLOW_SLURM_DIR:-/tmp/granflow-slurm}"
log() { echo "slurm-up: $*" >&2; }

if [ "$(id -u)" -ne 0 ]; then
    log "must run as root (installs packages and starts daemons)"
    exit 1
fi

need_install=0
for bin in /usr/sbin/slurmctld /usr/sbin/slurmd /usr/sbin/munged /usr/bin/sbatch; do
    [ -x "$bin" ] || need_install=1
done
if [ "$need_install" -eq 1 ]; then
    log "installing slurm-wlm, slurmctld, slurmd, munge, slurm-client (Debian packages)"
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout=900 install -y -qq \
        --no-install-recommends slurm-wlm slurmctld slurmd munge slurm-client >/dev/null
fi

# A cluster left over from an earlier run is stopped first, by its pid files.
if [ -d "$S/run" ]; then
    bash "$(dirname "$0")/slurm-down.sh" || true
fi

rm -rf "$S/state"
mkdir -p "$S/state/ctld" "$S/state/d" "$S/run" "$S/log"
cpus="$(nproc)"
mkdir -p /etc/slurm
cat >/etc/slurm/slurm.conf <<CONF
# Written by granflow's .ci/slurm-up.sh: a single-node test cluster on loopback.
ClusterName=local
SlurmctldHost=localhost
AuthType=auth/munge
CredType=cred/munge
SlurmUser=root
StateSaveLocation=$S/state/ctld
SlurmdSpoolDir=$S/state/d
SlurmctldPidFile=$S/run/slurmctld.pid
SlurmdPidFile=$S/run/slurmd.pid
SlurmctldLogFile=$S/log/slurmctld.log
SlurmdLogFile=$S/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
ReturnToService=2
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc=$S/log/jobcomp.log
NodeName=localhost NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=1000 State=UNKNOWN
PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP
CONF

# munged: the key is created by the package's post-install step.
# munged runs as user munge, so its pid file lives in a directory that user owns.
mkdir -p /run/munge "$S/run/munge"
chown munge:munge /run/munge "$S/run/munge"
runuser -u munge -- /usr/sbin/munged --pid-file="$S/run/munge/munged.pid" 2>"$S/log/munged.err" || {
    # munged refuses to start a second time on the same socket; one may already run.
    munge -n | unmunge >/dev/null 2>&1 || { cat "$S/log/munged.err" >&2; exit 1; }
    log "munged already running (not ours)"
}
munge -n | unmunge >/dev/null

/usr/sbin/slurmctld
/usr/sbin/slurmd -N localhost

# Wait (at most 60 s) until the node is idle.
for _ in $(seq 1 120); do
    state="$(sinfo --noheader --nodes=localhost --format=%T 2>/dev/null || true)"
    if [ "$state" = "idle" ]; then
        log "node localhost idle ($cpus CPUs); state in $S"
        exit 0
    fi
    sleep 0.5
done
log "node did not become idle (last state: '${state:-none}'); logs:"
tail -n 20 "$S/log/slurmctld.log" "$S/log/slurmd.log" >&2 || true
exit 1
