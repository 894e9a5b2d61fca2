#!/usr/bin/env bash
# Throw-away one-node Slurm cluster (munged + slurmctld + slurmd, localhost only),
# everything (key, sockets, state, logs, pids) inside one directory.
#
#   source scripts/slurm-local.sh
#   trap slurm_local_stop EXIT
#   slurm_local_start "$(mktemp -d)"   # exports SLURM_CONF, SLURM_LOCAL_DIR
# Call start in the script's own shell, not in $(...) or a pipeline: stop finds
# the cluster through SLURM_LOCAL_DIR (or `slurm_local_stop DIR`).
#   sbatch --wrap 'echo hi'; ...; cat "$(slurm_local_jobcomp)"
#
# Self-test: bash scripts/slurm-local.sh selftest
# Needs root (slurmd launches jobs as the submitting user) and the Debian
# packages slurm-wlm + munge. Ports: SLURM_LOCAL_PORT (default 16817) is the first
# one tried; the first two free ports at or above it are used.
#
# Safe to source from scripts using `set -euo pipefail`: every function uses
# locals, guards commands that may fail and never changes shell options.

# The daemons we start carry SLURM_LOCAL_TAG=<dir> in their environment. The
# slurmstepds (daemonized, so no parent link) get a fresh environment from slurmd
# holding only SLURM_CONF=<dir>/slurm.conf; job processes have that too (it is
# exported to sbatch) plus SLURM_JOB_ID. That is how stop finds exactly our
# processes and nobody else's, e.g. not a second cluster in another DIR.
SLURM_LOCAL_DIR=${SLURM_LOCAL_DIR:-}

_slurm_local_log() { printf 'slurm-local: %s\n' "$*" >&2; }

# Fields of /proc/$1/stat after "(comm)" into array _st: _st[0]=state, _st[1]=ppid.
# Builtins only: forks are slow (notably under gVisor) and we scan all of /proc.
_slurm_local_stat() {
    local line=""
    read -r line 2>/dev/null <"/proc/$1/stat" || return 1
    read -r -a _st <<<"${line##*) }"
}

# Alive and not a zombie (pid 1 here may be slow to reap daemonized orphans).
_slurm_local_alive() {
    local _st=()
    _slurm_local_stat "$1" && [[ ${_st[0]} != Z ]]
}

# pids of our live processes (see above) whose name starts with $2 (any if "").
_slurm_local_tagged() {
    local dir=$1 want=${2:-} p q comm skip=" " envs=() all _st=()
    # Never match ourselves or a caller (a caller may run inside one of our jobs).
    q=${BASHPID:-$$}
    while [[ -n $q && $q != 0 && $q != 1 ]]; do
        skip+="$q "
        _slurm_local_stat "$q" || break
        q=${_st[1]}
    done
    for p in /proc/[0-9]*; do
        p=${p#/proc/}
        [[ $skip == *" $p "* ]] && continue
        read -r comm 2>/dev/null <"/proc/$p/comm" || continue
        [[ $comm == "$want"* ]] || continue
        mapfile -d "" -t envs 2>/dev/null <"/proc/$p/environ" || continue
        ((${#envs[@]})) || continue # kernel threads, zombies
        printf -v all '\n%s' "${envs[@]}"
        all+=$'\n'
        if [[ $all != *$'\n'"SLURM_LOCAL_TAG=$dir"$'\n'* ]]; then
            [[ $all == *$'\n'"SLURM_CONF=$dir/slurm.conf"$'\n'* ]] || continue
            [[ $comm == slurmstepd* || $all == *$'\n'SLURM_JOB_ID=* ]] || continue
        fi
        _slurm_local_alive "$p" && echo "$p"
    done
    return 0
}

# First TCP port >= $1 nobody listens on, skipping $2.
_slurm_local_free_port() {
    local p=$1 skip=${2:-}
    while ((p < $1 + 500)); do
        if [[ $p != "$skip" ]] && [[ -z $(ss -Htln "sport = :$p" 2>/dev/null) ]]; then
            echo "$p"
            return 0
        fi
        p=$((p + 1))
    done
    return 1
}

# Wait (bounded, tenths of a second) until file $1 exists and is non-empty.
_slurm_local_wait_file() {
    local i
    for ((i = 0; i < $2; i++)); do
        [[ -s $1 ]] && return 0
        sleep 0.1
    done
    return 1
}

_slurm_local_dump_logs() {
    local f
    for f in "$SLURM_LOCAL_DIR"/munged.log "$SLURM_LOCAL_DIR"/slurmctld.log \
        "$SLURM_LOCAL_DIR"/slurmd.log "$SLURM_LOCAL_DIR"/*.out; do
        [[ -s $f ]] || continue
        printf '==== %s (last 40 lines)\n' "$f" >&2
        tail -n 40 "$f" >&2 || true
    done
}

slurm_local_jobcomp() {
    [[ -n $SLURM_LOCAL_DIR ]] || { _slurm_local_log "not started"; return 1; }
    echo "$SLURM_LOCAL_DIR/jobcomp.log"
}

slurm_local_start() {
    local dir=${1:?usage: slurm_local_start DIR} node mem cpus cport dport i state=""
    if [[ -n $SLURM_LOCAL_DIR ]] && [[ -n $(_slurm_local_tagged "$SLURM_LOCAL_DIR") ]]; then
        _slurm_local_log "already running in $SLURM_LOCAL_DIR"
        return 1
    fi
    [[ $(id -u) == 0 ]] || { _slurm_local_log "slurmd must run as root"; return 1; }
    mkdir -p "$dir"/state "$dir"/spool || return 1
    dir=$(cd "$dir" && pwd -P) || return 1
    # munged refuses a group/world-writable socket dir, and non-root clients
    # need to traverse it to reach the socket (mktemp -d gives 0700).
    chmod 0755 "$dir" || return 1
    SLURM_LOCAL_DIR=$dir
    export SLURM_LOCAL_DIR

    # slurmd registers under this name; it must resolve (we also pin NodeAddr).
    node=$(hostname -s)
    cpus=$(nproc)
    # Leave 10% (at least 512 MB) to the OS: slurmd drains the node if
    # RealMemory exceeds what it detects, and jobs need headroom.
    mem=$(free -m | awk '/^Mem:/ {r = int($2 * 0.9); if ($2 - r < 512) r = $2 - 512; print r}')
    cport=$(_slurm_local_free_port "${SLURM_LOCAL_PORT:-16817}") || return 1
    dport=$(_slurm_local_free_port "$((cport + 1))" "$cport") || return 1

    # munge: private key, socket, pid, log and seed, so the system munged (if
    # any) is neither needed nor disturbed. Slurm finds the socket via AuthInfo.
    rm -f "$dir/munge.key"
    if command -v mungekey >/dev/null; then
        mungekey --create --keyfile="$dir/munge.key" 2>/dev/null || return 1
    else
        dd if=/dev/urandom of="$dir/munge.key" bs=1024 count=1 status=none || return 1
    fi
    chmod 0400 "$dir/munge.key" || return 1
    # A reused DIR: slurmctld -c below restarts job ids at 1, so old entries
    # would alias new jobs in the completion log.
    : >"$dir/jobcomp.log" || return 1
    # --force: a stale socket left by a killed munged would otherwise block restart.
    SLURM_LOCAL_TAG=$dir munged --force --key-file="$dir/munge.key" \
        --socket="$dir/munge.socket" --pid-file="$dir/munged.pid" \
        --log-file="$dir/munged.log" --seed-file="$dir/munged.seed" \
        </dev/null >>"$dir/munged.out" 2>&1 ||
        { _slurm_local_log "munged failed"; _slurm_local_dump_logs; return 1; }
    _slurm_local_wait_file "$dir/munged.pid" 100 ||
        { _slurm_local_log "munged wrote no pid"; _slurm_local_dump_logs; return 1; }

    : >"$dir/plugstack.conf" # keep /etc/slurm/plugstack.conf (SPANK) out
    cat >"$dir/slurm.conf" <<EOF
ClusterName=local
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$cport
SlurmdPort=$dport
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge.socket
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
PlugStackConfig=$dir/plugstack.conf
# No cgroups (not available/wanted in containers): plain /proc tracking.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
# No slurmdbd, so no sacct: finished jobs are recorded in a text file instead.
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc=$dir/jobcomp.log
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
# Without this a job lacking --mem gets the whole node's memory and jobs serialize.
DefMemPerCPU=$((mem / cpus))
MpiDefault=none
MailProg=/bin/true # default /bin/mail is absent; avoids a startup error
ReturnToService=2
SchedulerType=sched/backfill
# Default batch_sched_delay=3 holds every new job ~3 s before it may start.
SchedulerParameters=batch_sched_delay=0
SlurmctldTimeout=10
SlurmdTimeout=10
MessageTimeout=5
KillWait=5
InactiveLimit=0
# Finished jobs stay visible to scontrol for 5 min (status scripts use that).
MinJobAge=300
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=debug Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
    export SLURM_CONF=$dir/slurm.conf

    # Daemon mode (no -D): they fork off and write their pid files, so they are
    # not jobs of the caller's shell (a bare `wait` there would hang otherwise).
    # -c: start from empty state even if DIR is reused.
    SLURM_LOCAL_TAG=$dir slurmctld -c -f "$SLURM_CONF" </dev/null >>"$dir/slurmctld.out" 2>&1 ||
        { _slurm_local_log "slurmctld failed"; _slurm_local_dump_logs; return 1; }
    SLURM_LOCAL_TAG=$dir slurmd -c -N "$node" -f "$SLURM_CONF" </dev/null >>"$dir/slurmd.out" 2>&1 ||
        { _slurm_local_log "slurmd failed"; _slurm_local_dump_logs; return 1; }

    for ((i = 0; i < 300; i++)); do
        state=$(sinfo -h -n "$node" -o %t 2>/dev/null) || state=""
        [[ $state == idle ]] && break
        sleep 0.1
    done
    if [[ $state != idle ]]; then
        _slurm_local_log "node '$node' not idle after 30 s (state '${state:-none}')"
        _slurm_local_dump_logs
        return 1
    fi
    _slurm_local_log "up in $dir (ports $cport/$dport, $cpus CPUs, $mem MB)"
}

# TERM the tagged processes named $2*, then KILL after $3 tenths of a second.
_slurm_local_kill() {
    local dir=$1 name=$2 i pids
    pids=$(_slurm_local_tagged "$dir" "$name")
    [[ -n $pids ]] || return 0
    _SLURM_LOCAL_KILLED+=" $pids"
    # shellcheck disable=SC2086 # pid list, split on purpose
    kill -TERM $pids 2>/dev/null || true
    for ((i = 0; i < $3; i++)); do
        pids=$(_slurm_local_tagged "$dir" "$name")
        [[ -n $pids ]] || return 0
        sleep 0.1
    done
    _slurm_local_log "$name did not stop, sending KILL to $pids"
    # shellcheck disable=SC2086
    kill -KILL $pids 2>/dev/null || true
    sleep 0.2
    return 0
}

# DIR defaults to the last start's; pass it if start ran in a subshell.
slurm_local_stop() {
    local dir=${1:-${SLURM_LOCAL_DIR:-}} ids i p
    [[ -n $dir ]] || return 0
    _SLURM_LOCAL_KILLED=""
    # Cancel jobs first so slurmstepd can kill their processes cleanly.
    if [[ -n $(_slurm_local_tagged "$dir" slurmctld) ]]; then
        ids=$(SLURM_CONF=$dir/slurm.conf squeue -h -o %A 2>/dev/null) || ids=""
        if [[ -n $ids ]]; then
            # shellcheck disable=SC2086 # job id list
            SLURM_CONF=$dir/slurm.conf scancel $ids 2>/dev/null || true
            # KillWait=5: slurmstepd escalates TERM to KILL and exits by then.
            for ((i = 0; i < 80; i++)); do
                [[ -z $(_slurm_local_tagged "$dir" slurmstepd) ]] && break
                sleep 0.1
            done
        fi
    fi
    _slurm_local_kill "$dir" slurmd 100
    _slurm_local_kill "$dir" slurmstepd 30
    _slurm_local_kill "$dir" slurmctld 100
    _slurm_local_kill "$dir" munged 50
    _slurm_local_kill "$dir" "" 30 # job processes orphaned by a killed slurmstepd
    rm -f "$dir/munge.socket" "$dir/munge.socket.lock" 2>/dev/null || true
    # Daemons are orphans: give init a moment (~1 s seen) to reap the zombies
    # so that a `pgrep` right after stop comes back empty.
    for ((i = 0; i < 30; i++)); do
        for p in $_SLURM_LOCAL_KILLED; do
            [[ -e /proc/$p ]] && break
            p=""
        done
        [[ -z ${p:-} ]] && break
        sleep 0.1
    done
    return 0
}

_slurm_local_selftest() {
    set -euo pipefail
    local dir t0 t1 j1 j2 i line left
    dir=$(mktemp -d /tmp/slurm-local.XXXXXX)
    _SLURM_LOCAL_SELFTEST_DIR=$dir # the EXIT trap runs after locals are gone
    trap 'slurm_local_stop; rm -rf "$_SLURM_LOCAL_SELFTEST_DIR"' EXIT
    t0=${EPOCHREALTIME/[.,]/}
    slurm_local_start "$dir"
    t1=${EPOCHREALTIME/[.,]/}
    echo "start took $(((t1 - t0) / 1000)) ms"
    sinfo
    cd "$dir"
    j1=$(sbatch --parsable --wrap 'echo hi')
    cat >"$dir/two-steps.sh" <<'EOF'
#!/bin/bash
#SBATCH --ntasks=1 --mem=100M
srun echo step-one
srun hostname
EOF
    j2=$(sbatch --parsable "$dir/two-steps.sh")
    echo "submitted $j1 (wrap) and $j2 (two steps)"
    for ((i = 0; i < 600; i++)); do
        [[ -z $(squeue -h -j "$j1,$j2" -o %A 2>/dev/null) ]] && break
        sleep 0.1
    done
    echo "--- jobcomp.log"
    cat "$(slurm_local_jobcomp)"
    echo "--- outputs"
    cat "slurm-$j1.out" "slurm-$j2.out"
    for i in "$j1" "$j2"; do
        line=$(grep "^JobId=$i " "$(slurm_local_jobcomp)") || line=""
        [[ $line == *" JobState=COMPLETED "* ]] || { echo "FAIL: job $i not COMPLETED"; exit 1; }
    done
    grep -qx hi "slurm-$j1.out" && grep -qx step-one "slurm-$j2.out"
    cd /
    t0=${EPOCHREALTIME/[.,]/}
    slurm_local_stop "$dir"
    t1=${EPOCHREALTIME/[.,]/}
    echo "stop took $(((t1 - t0) / 1000)) ms"
    left=$(_slurm_local_tagged "$dir")
    if [[ -n $left ]]; then
        echo "FAIL: left behind:"; ps -o pid,comm,args -p "${left//$'\n'/,}"; exit 1
    fi
    echo "selftest OK"
}

if [[ ${BASH_SOURCE[0]} == "$0" ]]; then
    case ${1:-} in
    selftest) _slurm_local_selftest ;;
    *) echo "usage: bash $0 selftest   (or source it)" >&2; exit 2 ;;
    esac
fi
