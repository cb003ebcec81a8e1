#!/usr/bin/env bash
# The README's main command: builds the project, then runs the simulated cell
# (machine tool, robot, bar feeder: apps/cell) and the MTConnect bridge
# together inside one private, loopback-only network namespace.
#
# Usage:
#   ./scripts/start.sh [--no-build] [--secure] [--port N] [--domain D] [cell options]
#                                      run the cell and the bridge (Ctrl-C stops both);
#                                      bridge port default 5000, DDS domain default 110;
#                                      --secure: DDS-Security for every participant, with
#                                      a test CA made on first use in .pki/ (gitignored;
#                                      scripts/security/make-pki.sh, scripts/security/cell.txt)
#   ./scripts/start.sh --query PATH    from another terminal: GET PATH from the running bridge
#   ./scripts/start.sh --enter [CMD]   from another terminal: a shell (or CMD) inside the namespace
#   ./scripts/start.sh --forward [PORT]
#                                      from another terminal, opt-in: relay 127.0.0.1:PORT on the
#                                      host (default: the bridge's port) to the bridge's HTTP port
#                                      in the namespace, for a browser on the host (Ctrl-C stops;
#                                      it also stops with the cell)
#
# Cell options go to mtc-cell: --cycles N, --duration S, --seed N, --fail-every K,
# --pace-ms MS, --comms-loss-every S, --heartbeat-ms MS, --missed-heartbeats N
# (the bridge gets these two as well), --threads (see `build/apps/mtc-cell --help`).
# The namespace has no route to anything but itself, so a browser outside it
# cannot reach the bridge: --query and --enter step into it with nsenter, and
# --forward relays HTTP connections into it (socat on the host, bound to
# 127.0.0.1; each connection is carried by a socat that nsenter starts inside
# the namespace). Only the bridge's HTTP port crosses: DDS stays inside, where
# it is also confined by the transport this script chooses for the cell and
# the bridge (--transport loopback: UDP on 127.0.0.1 and shared memory,
# unicast discovery; docs/runtime-qos.md, Transports); the tools' own
# default is the network.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${MTC_BUILD_DIR:-$root/build}"
# Where the running cell leaves its namespace's pid and its port for --query
# and --enter (tests point MTC_CELL_STATE_DIR elsewhere so they never touch
# the state of a cell a person is running from the same build).
state="${MTC_CELL_STATE_DIR:-$build}"
pidfile="$state/mtc-cell.netns.pid"  # a process inside the running cell's namespace
port_file="$state/mtc-cell.port"
tls_file="$state/mtc-cell.https-ca"  # --secure: the CA --query verifies the bridge with
domain=110                            # DDS domain of the cell (ids 100-119: cell and benchmarks)
pki="${MTC_PKI_DIR:-$root/.pki}"      # --secure: the test CA and the cell's identities
secure=0
port=5000

usage() { awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "${BASH_SOURCE[0]}"; }
usage_error() { echo "start.sh: $*" >&2; usage >&2; exit 2; }

# Prints the pid of a process in the running cell's namespace, or fails.
cell_ns_pid() {
  local pid
  pid="$(cat "$pidfile" 2>/dev/null || true)"
  if [ -z "$pid" ] || [ ! -e "/proc/$pid/ns/net" ] ||
     [ "$(readlink "/proc/$pid/ns/net")" = "$(readlink /proc/self/ns/net)" ]; then
    echo "start.sh: no cell is running (start one with ./scripts/start.sh)" >&2
    return 1
  fi
  echo "$pid"
}

# Prints the nsenter command line that steps into the namespace of process
# $1. netns-run.sh gives root a plain network namespace and others a user
# namespace as well.
nsenter_line() {
  if [ "$(id -u)" -eq 0 ]; then
    echo "nsenter --target $1 --net --"
  else
    echo "nsenter --target $1 --user --net --preserve-credentials --"
  fi
}

# Runs a command inside the running cell's namespace.
in_cell_ns() {
  local pid
  pid="$(cell_ns_pid)" || exit 1
  # shellcheck disable=SC2046  # the line is words without spaces inside
  exec $(nsenter_line "$pid") "$@"
}

# Relays 127.0.0.1:$1 on this side to the bridge's port inside the running
# cell's namespace until the cell stops (or Ctrl-C). HTTP only: one TCP
# port, to 127.0.0.1 inside; no DDS crosses.
forward_to_cell() {
  local host_port="$1" pid relay_pid watch_pid rc=0
  case "$host_port" in '' | *[!0-9]*) usage_error "--forward needs a port number, not '$host_port'" ;; esac
  command -v socat >/dev/null ||
    { echo "start.sh: --forward needs socat (run scripts/setup-deps.sh)" >&2; exit 1; }
  pid="$(cell_ns_pid)" || exit 1
  socat -lpstart.sh-forward "TCP-LISTEN:$host_port,bind=127.0.0.1,reuseaddr,fork" \
    "EXEC:$(nsenter_line "$pid") socat STDIO TCP\:127.0.0.1\:$port" &
  relay_pid=$!
  tail --pid="$pid" -f /dev/null &  # ends when the cell's start.sh ends
  watch_pid=$!
  trap 'kill "$relay_pid" "$watch_pid" 2>/dev/null || true' EXIT
  echo "start.sh: http://127.0.0.1:$host_port/ on this host now reaches the bridge" \
    "(port $port inside the cell's namespace); Ctrl-C stops the forward" >&2
  wait -n "$relay_pid" "$watch_pid" || rc=$?
  if ! kill -0 "$pid" 2>/dev/null; then
    echo "start.sh: the cell stopped; forward closed" >&2
    exit 0
  fi
  echo "start.sh: the forward stopped (socat exit code $rc)" >&2
  exit 1
}

case "${1:-}" in
  -h|--help) usage; exit 0 ;;
  --query)
    path="${2:-/current}"
    case "$path" in /*) ;; *) path="/$path" ;; esac
    [ -r "$port_file" ] && port="$(cat "$port_file")"
    if [ -r "$tls_file" ]; then
      in_cell_ns curl -sS --fail-with-body --max-time 10 --cacert "$(cat "$tls_file")" \
        "https://127.0.0.1:${port}${path}"
    fi
    in_cell_ns curl -sS --fail-with-body --max-time 10 "http://127.0.0.1:${port}${path}" ;;
  --enter)
    shift
    if [ $# -eq 0 ]; then
      echo "start.sh: shell inside the cell's namespace; try: curl -s http://127.0.0.1:$port/current" >&2
      echo "          or: $build/apps/mtc watch --transport loopback --domain $domain. exit leaves." >&2
      in_cell_ns bash -i
    fi
    in_cell_ns "$@" ;;
  --forward)
    [ -r "$port_file" ] && port="$(cat "$port_file")"
    forward_to_cell "${2:-$port}" ;;
esac

# ---------------------------------------------------------------- run
build_first=1
cell_args=()
# The bridge's observer must use the cell's lease: a reader whose lease is
# shorter than the writers' does not match them (and Fast DDS detects loss
# with the reader's own lease). Both default to the runtime's timing
# (qos::Timing), so the flags are handed to the bridge only when given.
bridge_timing=()
need_value() { [ $# -ge 2 ] || usage_error "$1 needs a value"; }
while [ $# -gt 0 ]; do
  case "$1" in
    -h | --help) usage; exit 0 ;;
    --no-build) build_first=0; shift ;;
    --secure) secure=1; shift ;;
    --heartbeat-ms | --missed-heartbeats)
      need_value "$@"; bridge_timing+=("$1" "$2"); cell_args+=("$1" "$2"); shift 2 ;;
    --port) need_value "$@"; port="$2"; shift 2 ;;
    --domain) need_value "$@"; domain="$2"; shift 2 ;;
    --inner) shift ;;  # set by the re-exec below
    # mtc-cell checks the values; an unknown option stops here, before a build.
    --cycles | --duration | --seed | --fail-every | --pace-ms | --comms-loss-every)
      need_value "$@"; cell_args+=("$1" "$2"); shift 2 ;;
    --threads) cell_args+=("$1"); shift ;;
    *) usage_error "unknown option '$1'" ;;
  esac
done

# --secure: a test CA for this machine only, made once and reused after
# (identities are remade when the cell description is newer than them), and
# the bridge's HTTPS certificate, self-signed for 127.0.0.1 (its own CA).
# Made before entering the namespace, or inside when already in one.
if [ "$secure" = 1 ]; then
  if [ ! -r "$pki/ca/ca.pem" ]; then
    "$root/scripts/security/make-pki.sh" --cell "$root/scripts/security/cell.txt" --out "$pki"
  elif [ "$root/scripts/security/cell.txt" -nt "$pki/cell-machine/permissions.p7s" ]; then
    "$root/scripts/security/make-pki.sh" --cell "$root/scripts/security/cell.txt" \
      --out "$pki" --ca "$pki/ca"
  fi
  if [ ! -r "$pki/https/cert.pem" ]; then
    mkdir -p "$pki/https"
    openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -days 365 \
      -keyout "$pki/https/key.pem" -out "$pki/https/cert.pem" -subj "/CN=127.0.0.1" \
      -addext "subjectAltName=IP:127.0.0.1" 2>/dev/null
    chmod 600 "$pki/https/key.pem"
  fi
fi

if [ "${MTC_IN_NETNS:-}" != "1" ]; then
  if [ "$build_first" = 1 ]; then
    "$root/scripts/build.sh"
  fi
  # SHM segments of a cell killed earlier would only confuse the new one.
  fastdds shm clean >/dev/null 2>&1 || true
  secure_args=()
  [ "$secure" = 1 ] && secure_args=(--secure)
  exec "$root/scripts/netns-run.sh" "$0" --inner --no-build --port "$port" --domain "$domain" \
    "${secure_args[@]}" "${cell_args[@]}"
fi

# ------------------------------------------- inside the namespace from here
cell="$build/apps/mtc-cell"
bridge="$build/apps/mtc-bridge"
bridge_log="$build/mtc-bridge.log"
[ -x "$cell" ] || { echo "start.sh: $cell is not built" >&2; exit 1; }

bridge_security=()
cell_security=()
if [ "$secure" = 1 ]; then
  bridge_security=(--security "$pki/mtc-bridge" --tls-certificate "$pki/https/cert.pem"
                   --tls-private-key "$pki/https/key.pem")
  cell_security=(--security "$pki")
fi
scheme=http
curl_tls=()
if [ "$secure" = 1 ]; then
  scheme=https
  curl_tls=(--cacert "$pki/https/cert.pem")
fi
bridge_pid=""
cell_pid=""
cleanup() {
  [ -n "$cell_pid" ] && kill -TERM "$cell_pid" 2>/dev/null || true
  if [ -n "$bridge_pid" ] && kill -0 "$bridge_pid" 2>/dev/null; then
    kill -TERM "$bridge_pid" 2>/dev/null || true
    for _ in $(seq 50); do kill -0 "$bridge_pid" 2>/dev/null || break; sleep 0.1; done
    kill -KILL "$bridge_pid" 2>/dev/null || true
    wait "$bridge_pid" 2>/dev/null || true
  fi
  rm -f "$pidfile" "$port_file" "$tls_file"
}
trap cleanup EXIT
echo $$ >"$pidfile"
echo "$port" >"$port_file"
if [ "$secure" = 1 ]; then echo "$pki/https/cert.pem" >"$tls_file"; else rm -f "$tls_file"; fi

if [ -x "$bridge" ]; then
  # Same heartbeat as the cell, so the bridge matches the stations' writers
  # and declares a device lost when the stations would.
  # 127.0.0.1 only, even inside the namespace: --forward reaches it there.
  "$bridge" --transport loopback --domain-ids "$domain" --server-ip 127.0.0.1 --port "$port" \
    "${bridge_timing[@]}" \
    "${bridge_security[@]}" \
    >"$bridge_log" 2>&1 &
  bridge_pid=$!
  # Wait until the agent answers (it also needs no device yet to answer).
  for _ in $(seq 100); do
    curl -s -o /dev/null --max-time 1 "${curl_tls[@]}" "$scheme://127.0.0.1:$port/probe" && break
    kill -0 "$bridge_pid" 2>/dev/null || break
    sleep 0.1
  done
  if ! kill -0 "$bridge_pid" 2>/dev/null; then
    echo "start.sh: the bridge did not start; its log ($bridge_log):" >&2
    tail -n 20 "$bridge_log" >&2
    exit 1
  fi
else
  echo "start.sh: $bridge is not built; running the cell without the MTConnect bridge" >&2
fi

cat <<EOF
================================================================================
 mtconnect-dds simulated cell: machine tool + robot + bar feeder on DDS domain $domain
 DDS-Security: $([ "$secure" = 1 ] && echo "on (identities in $pki)" || echo "off (--secure turns it on)")
 running in a private loopback-only network namespace (pid $$).
 MTConnect agent (mtc-bridge): $scheme://127.0.0.1:$port/probe  /current  /sample
   (log: $bridge_log)
 That address exists only inside the namespace. From another terminal:
   ./scripts/start.sh --query /current               # current values of every data item
   ./scripts/start.sh --query '/sample?count=50'     # the last handshakes as they happened
   ./scripts/start.sh --enter                        # a shell inside: curl, $build/apps/mtc
   ./scripts/start.sh --forward                      # opt-in: http://127.0.0.1:$port/ on the host
                                                     # (the live page in a browser; HTTP only)
 Stop with Ctrl-C.
================================================================================
EOF

# The cell runs as a background job so that SIGINT/SIGTERM reach this shell's
# trap at once; the trap hands them on and the loop waits for a clean exit.
"$cell" --transport loopback --domain "$domain" "${cell_security[@]}" "${cell_args[@]}" &
cell_pid=$!
trap 'kill -TERM "$cell_pid" 2>/dev/null || true' INT TERM
rc=0
while :; do
  rc=0
  wait "$cell_pid" || rc=$?
  kill -0 "$cell_pid" 2>/dev/null || break
done
# A wait cut short by the trap says 130/143; bash still knows the real status.
if [ "$rc" -gt 128 ]; then
  rc=0
  wait "$cell_pid" || rc=$?
fi
cell_pid=""
echo "start.sh: cell stopped (exit code $rc)"
exit "$rc"
