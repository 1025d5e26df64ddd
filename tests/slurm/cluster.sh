# shellcheck shell=bash
# A one-node SLURM cluster on this machine, for tests: munged, slurmctld and slurmd, with every
# file (config, munge key and socket, state, spool, logs, pid files) in one folder, so that
# /etc/slurm, /etc/munge and a SLURM or munge the system runs are neither read nor touched.
# Needs root (slurmd starts the jobs) and Debian's slurm-wlm and munge. Sourced by
# test_array_job.sh; by hand:
#   source tests/slurm/cluster.sh; cluster_start /tmp/c; export SLURM_CONF=/tmp/c/slurm.conf
#   ... sbatch, squeue ...; cluster_stop /tmp/c

# shellcheck disable=SC2034  # the programs a user of these functions checks for
cluster_programs=(munged mungekey slurmctld slurmd sbatch squeue sinfo scontrol scancel)

# The daemons in the order they start; they stop in the reverse order.
cluster_daemons=(munged slurmctld slurmd)

# A TCP port on 127.0.0.1 that nothing listens on, from $1 upwards, skipping $2 (already taken).
cluster_free_port() {
  local port=$1
  while [ "$port" = "${2:-}" ] || (exec 3<>"/dev/tcp/127.0.0.1/$port") 2> /dev/null; do
    port=$((port + 1))
  done
  echo "$port"
}

# Is process $1 alive and named $2? (A stale pid file may name a reused pid; a daemon that exited
# stays a zombie where the container's init does not reap it.)
cluster_running() {
  local stat
  stat=$(cat "/proc/$1/stat" 2> /dev/null) || return 1
  [[ $stat == "$1 ($2) "* ]] && [[ $stat != "$1 ($2) Z "* ]]
}

# Cancels the cluster's jobs (a job's slurmstepd would outlive slurmd), then stops the daemons
# whose pid files are in $1/run: SIGTERM, then SIGKILL after 10 s. Safe to call on a folder a
# killed run left behind, and on a cluster that never started.
cluster_stop() {
  local dir=$1 i name pid
  if pid=$(cat "$dir/run/slurmctld.pid" 2> /dev/null) && cluster_running "$pid" slurmctld &&
    SLURM_CONF=$dir/slurm.conf scancel --quiet --partition=test 2> /dev/null; then
    for _ in $(seq 50); do
      [ -z "$(SLURM_CONF=$dir/slurm.conf squeue -h -o %i 2> /dev/null)" ] && break
      sleep 0.2
    done
  fi
  for ((i = ${#cluster_daemons[@]} - 1; i >= 0; i--)); do
    name=${cluster_daemons[i]}
    pid=$(cat "$dir/run/$name.pid" 2> /dev/null) || continue
    cluster_running "$pid" "$name" || continue
    kill -TERM "$pid" 2> /dev/null || true
    for _ in $(seq 100); do
      cluster_running "$pid" "$name" || break
      sleep 0.1
    done
    if cluster_running "$pid" "$name"; then
      echo "cluster: $name (pid $pid) ignored SIGTERM for 10 s; killing it" >&2
      kill -KILL "$pid" 2> /dev/null || true
    fi
  done
}

# Prints the daemons' logs (for a failure).
cluster_logs() {
  local log
  for log in "$1"/log/*.log; do
    [ -f "$log" ] || continue
    echo "----- $log"
    tail -n 60 "$log"
  done
}

# Writes $1/slurm.conf and starts munged, slurmctld and slurmd; returns once the node is idle
# (at most 30 s). The folder is emptied first (after stopping daemons a killed run left in it).
cluster_start() {
  local dir=$1
  cluster_stop "$dir"
  rm -rf "$dir"
  mkdir -p "$dir"/{key,run,state,spool,log}
  dir=$(cd "$dir" && pwd)
  # slurmd makes a Unix socket per job step in its spool folder: such paths hold 108 bytes.
  if [ ${#dir} -gt 70 ]; then
    echo "cluster: the folder $dir is too long (${#dir} > 70 characters) for SLURM's sockets" >&2
    return 1
  fi
  chmod 700 "$dir/key"
  chmod 755 "$dir/run"

  mungekey --create --keyfile="$dir/key/munge.key" > /dev/null
  # --force: all clients run as root, so the socket may sit below a folder others cannot enter
  # (a checkout in /root), which munged otherwise refuses.
  munged --force --key-file="$dir/key/munge.key" --seed-file="$dir/key/munged.seed" \
    --socket="$dir/run/munge.socket" --pid-file="$dir/run/munged.pid" \
    --log-file="$dir/log/munged.log"

  # Ports from 20000 + pid % 12000 (below the ephemeral range), so that two runs, or a system
  # SLURM (6817, 6818), do not collide.
  local ctld_port slurmd_port
  ctld_port=$(cluster_free_port $((20000 + ($$ % 12000))))
  slurmd_port=$(cluster_free_port $((ctld_port + 1)) "$ctld_port")

  # The node as slurmd sees it (sockets, cores, threads); a node configured with more CPUs or
  # memory than it has would be drained. No cgroups (containers often lack them): Linux process
  # tracking, no task binding, no accounting.
  local node
  node=$(slurmd -C | head -n 1 | sed 's/^NodeName=[^ ]*/NodeName=localhost NodeAddr=127.0.0.1/')
  cat > "$dir/slurm.conf" <<EOF
ClusterName=fmcwtest
SlurmctldHost=localhost
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/run/munge.socket
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/run/slurmctld.pid
SlurmdPidFile=$dir/run/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
MailProg=/bin/true
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/builtin
MpiDefault=none
ReturnToService=2
$node State=UNKNOWN
PartitionName=test Nodes=localhost Default=YES MaxTime=INFINITE State=UP
EOF

  slurmctld -f "$dir/slurm.conf"
  slurmd -f "$dir/slurm.conf" -N localhost

  local state=""
  for _ in $(seq 150); do
    state=$(SLURM_CONF=$dir/slurm.conf sinfo -h -n localhost -o %T 2> /dev/null || true)
    [ "$state" = idle ] && return 0
    sleep 0.2
  done
  echo "cluster: the node is not idle after 30 s (state: '${state:-none}')" >&2
  return 1
}
