#!/bin/sh
# Snakemake's --cluster-status for Slurm (pipelines/slurm/config.yaml):
#   status.sh JOBID      prints running, success or failed
# JOBID is what `sbatch --parsable` printed ("id" or "id;cluster"). Asks
# sacct for the job's state; while sacct does not know the job yet (just
# submitted) or cannot be reached, the job counts as running.
if [ $# -ne 1 ]; then
  echo "usage: $0 JOBID" >&2
  exit 2
fi
id=${1%%;*}
case $id in
  '' | *[!0-9_.]*) echo "status.sh: error: '$1' is not a Slurm job id" >&2; exit 2 ;;
esac
state=$(sacct -j "$id" -X -n -P -o State 2>/dev/null | head -n 1)
# "CANCELLED by 123" -> CANCELLED
state=${state%% *}
case $state in
  COMPLETED) echo success ;;
  FAILED | CANCELLED* | TIMEOUT | OUT_OF_MEMORY | NODE_FAIL | PREEMPTED | BOOT_FAIL | DEADLINE | REVOKED) echo failed ;;
  *) echo running ;;
esac
