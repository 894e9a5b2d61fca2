#!/usr/bin/env bash
# Snakemake --cluster-status for a Slurm without accounting (no slurmdbd, so
# no sacct), e.g. the one from scripts/slurm-local.sh. Usage: status.sh JOBID
# Snakemake aborts the whole run if this exits non-zero or prints anything but
# one line of success/running/failed, so every path below ends in exit 0.
set -uo pipefail
id=${1%%;*} # `sbatch --parsable` may print "jobid;cluster"

map() { # Slurm job state -> Snakemake word
    case $1 in
    COMPLETED) echo success ;;
    PENDING | CONFIGURING | RUNNING | COMPLETING | SUSPENDED | REQUEUED | REQUEUE_* | \
        RESIZING | SIGNALING | STAGE_OUT | STOPPED | RESV_DEL_HOLD) echo running ;;
    *) echo failed ;; # FAILED CANCELLED TIMEOUT OUT_OF_MEMORY NODE_FAIL BOOT_FAIL ...
    esac
}

# 1) Jobs stay known to slurmctld for MinJobAge seconds after they end.
if out=$(scontrol -o show job "$id" 2>&1); then
    state=$(sed -n '1s/.* JobState=\([A-Z_]*\).*/\1/p' <<<"$out")
    if [[ -n $state ]]; then map "$state"; exit 0; fi
elif [[ $out != *"Invalid job id"* ]]; then
    # Controller busy or restarting: say running, Snakemake will ask again.
    echo "status.sh: scontrol failed for $id: $out" >&2
    echo running
    exit 0
fi

# 2) Purged from slurmctld: the jobcomp/filetxt log has the final state.
loc=""
[[ -r ${SLURM_CONF:-/etc/slurm/slurm.conf} ]] &&
    loc=$(sed -n 's/^JobCompLoc=//p' "${SLURM_CONF:-/etc/slurm/slurm.conf}" | tail -n 1)
[[ -n $loc ]] || loc=$(scontrol show config 2>/dev/null | sed -n 's/^JobCompLoc *= *//p')
line=""
[[ -r $loc ]] && line=$(grep "^JobId=$id " "$loc" | tail -n 1) # last one wins after a requeue
state=$(sed -n 's/.* JobState=\([A-Z_]*\).*/\1/p' <<<"$line")
if [[ -n $state ]]; then
    map "$state"
else
    echo "status.sh: job $id unknown to slurmctld and not in '${loc:-no JobCompLoc}'" >&2
    echo failed
fi
exit 0
