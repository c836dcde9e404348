# Sourced by the scripts that drive navsim and navd together (warehouse-runs, office3d-runs,
# street-runs): starts both on DDS domain $domain with navd's gRPC on 127.0.0.1:$port, waits for
# navd's first pose (navd answers health before it; a mission needs the pose), and stops both on
# stack_stop or when the script exits. $bin is the build folder.
#   stack_start LOG_PREFIX NAVSIM_ARGS... -- NAVD_ARGS...   (LOG_PREFIX.navsim.log, LOG_PREFIX.navd.log)
stack_stop() {
  [ -n "${navd_pid:-}" ] && kill -TERM "$navd_pid" 2>/dev/null && wait "$navd_pid" 2>/dev/null || true
  [ -n "${sim_pid:-}" ] && kill -TERM "$sim_pid" 2>/dev/null && wait "$sim_pid" 2>/dev/null || true
  navd_pid="" sim_pid=""
}
trap stack_stop EXIT
stack_start() {
  local prefix=$1 sim_args=() navd_args=()
  shift
  while [ $# -gt 0 ] && [ "$1" != -- ]; do sim_args+=("$1"); shift; done
  [ $# -eq 0 ] || shift
  navd_args=("$@")
  "$bin/simulator/navsim" "${sim_args[@]}" --domain "$domain" >"$prefix.navsim.log" 2>&1 &
  sim_pid=$!
  "$bin/server/navd" --use-sim-time --domain "$domain" --listen "127.0.0.1:$port" "${navd_args[@]}" >"$prefix.navd.log" 2>&1 &
  navd_pid=$!
  for _ in $(seq 500); do "$bin/client_lib/navctl" --server "127.0.0.1:$port" pose >/dev/null 2>&1 && break; sleep 0.02; done
}
