#!/usr/bin/env bash
# Starts a one-node Slurm cluster on this machine (Debian 12, root), to submit
# docs/examples/slurm-array.sh for real:
#   scripts/slurm-one-node.sh && mkdir -p out && sbatch --wait docs/examples/slurm-array.sh
# Idempotent: does nothing when sinfo already answers. Refuses to replace an existing
# /etc/slurm/slurm.conf, so it never touches a real cluster's configuration.
set -euo pipefail
if sinfo -h >/dev/null 2>&1; then
  echo "slurm-one-node: a cluster already answers:"; sinfo
  exit 0
fi
if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q slurm-wlm munge >/dev/null
fi
conf=/etc/slurm/slurm.conf
if [ -e "$conf" ] && ! grep -q "^# written by refraster scripts/slurm-one-node.sh" "$conf"; then
  echo "slurm-one-node: $conf exists and is not ours; not replacing it" >&2
  exit 2
fi
host="$(hostname -s)"
mkdir -p /run/munge /var/log/munge /var/lib/munge /var/lib/slurm/slurmd \
  /var/lib/slurm/slurmctld /var/log/slurm
chown munge:munge /run/munge /var/log/munge /var/lib/munge
pgrep -x munged >/dev/null || runuser -u munge -- /usr/sbin/munged
# No cgroups in a container: track processes by parent and bind nothing.
cat > "$conf" <<CONF
# written by refraster scripts/slurm-one-node.sh
ClusterName=refraster-local
SlurmctldHost=$host
AuthType=auth/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
SlurmUser=root
SlurmctldPidFile=/run/slurmctld.pid
SlurmdPidFile=/run/slurmd.pid
SlurmdSpoolDir=/var/lib/slurm/slurmd
StateSaveLocation=/var/lib/slurm/slurmctld
SlurmctldLogFile=/var/log/slurm/slurmctld.log
SlurmdLogFile=/var/log/slurm/slurmd.log
NodeName=$host CPUs=$(nproc) State=UNKNOWN
PartitionName=local Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
pgrep -x slurmctld >/dev/null || slurmctld
pgrep -x slurmd >/dev/null || slurmd
for _ in $(seq 30); do
  if sinfo -h -o %t 2>/dev/null | grep -q idle; then sinfo; exit 0; fi
  sleep 1
done
echo "slurm-one-node: the node did not come up; see /var/log/slurm/" >&2
exit 1
