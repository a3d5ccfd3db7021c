#!/usr/bin/env bash
# Two hdof daemons behind Debian's nginx on loopback, configured from docker/nginx.conf (its
# upstream servers and listen port replaced, temp paths moved to a scratch directory): a short
# `hdof load` through the proxy must run without errors, and both daemons must have served
# sessions (their own /metrics). Usage: test_proxy.sh HDOF_BINARY SOURCE_DIR
set -euo pipefail

hdof="$1"
source_dir="$2"
nginx="$(command -v nginx || echo /usr/sbin/nginx)"
[[ -x "$nginx" ]] || { echo "test_proxy: nginx is not installed (scripts/setup installs nginx-light)" >&2; exit 1; }

scratch="$(mktemp -d /tmp/hdof-proxy-test.XXXXXX)"
pids=()
cleanup() {
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do wait "$pid" 2>/dev/null || true; done
  rm -rf "$scratch"
}
trap cleanup EXIT
fail() {
  echo "test_proxy: $*" >&2
  for log in "$scratch"/*.log; do echo "--- $log" >&2; tail -n 20 "$log" >&2; done
  exit 1
}

# GET PATH from 127.0.0.1:PORT; the body on stdout.
http_get() {
  exec 3<>"/dev/tcp/127.0.0.1/$1" || return 1
  printf 'GET %s HTTP/1.0\r\nHost: 127.0.0.1\r\n\r\n' "$2" >&3
  sed '1,/^\r$/d' <&3
  exec 3<&-
}

# A daemon on a free port (started here, so that cleanup knows its pid).
start_daemon() {
  echo '{"mode": "postprocess", "max_sessions": 8}' >"$scratch/$1.json"
  "$hdof" serve --port 0 --config "$scratch/$1.json" >"$scratch/$1.out" 2>"$scratch/$1.log" &
  pids+=($!)
}
# The port a started daemon prints.
daemon_port() {
  for _ in $(seq 600); do
    local port
    port="$(grep -oE ':[0-9]+/' "$scratch/$1.out" | tr -d :/ || true)"
    if [[ -n "$port" ]]; then echo "$port"; return; fi
    sleep 0.1
  done
  fail "$1 did not start"
}
start_daemon daemon1
start_daemon daemon2
port1="$(daemon_port daemon1)"
port2="$(daemon_port daemon2)"

# nginx on a free port: a few tries at random ones.
started=""
for _ in $(seq 20); do
  proxy_port=$((20000 + RANDOM % 30000))
  mkdir -p "$scratch/nginx"
  temp_paths=""
  for kind in client_body proxy fastcgi uwsgi scgi; do
    if "$nginx" -V 2>&1 | grep -q -- "--http-${kind//_/-}-temp-path"; then
      temp_paths+="  ${kind}_temp_path $scratch/nginx/$kind;\n"
    fi
  done
  sed -e "/^ *server hdof-[0-9]*:8080/d" \
      -e "s|^\( *\)# daemons: one line each|\1server 127.0.0.1:$port1;\n\1server 127.0.0.1:$port2;|" \
      -e "s|^\( *\)listen 8080;|\1listen 127.0.0.1:$proxy_port;|" \
      -e "s|^http {|pid $scratch/nginx/nginx.pid;\nhttp {\n$temp_paths|" \
      -e "s|^worker_processes auto;|worker_processes 1;|" \
      "$source_dir/docker/nginx.conf" >"$scratch/nginx.conf"
  "$nginx" -t -q -p "$scratch/nginx" -c "$scratch/nginx.conf" -e "$scratch/nginx.log" \
    || fail "nginx -t rejects the generated config"
  "$nginx" -p "$scratch/nginx" -c "$scratch/nginx.conf" -e "$scratch/nginx.log" &
  pids+=($!)
  for _ in $(seq 50); do
    if http_get "$proxy_port" /healthz 2>/dev/null | grep -q '"status":"ok"'; then
      started=yes
      break
    fi
    kill -0 "${pids[-1]}" 2>/dev/null || break
    sleep 0.1
  done
  [[ -n "$started" ]] && break
done
[[ -n "$started" ]] || fail "nginx did not start"

# A fixed affinity key spreads these six sessions over both daemons (consistent hash).
"$hdof" load --url "ws://127.0.0.1:$proxy_port/session" --sessions 6 --duration 3 \
  --mode postprocess --size 96x54 --affinity proxy-test --json >"$scratch/load.json" \
  2>"$scratch/load.log" || fail "hdof load through the proxy failed: $(cat "$scratch/load.json")"
grep -q '"errors": 0' "$scratch/load.json" || fail "errors: $(cat "$scratch/load.json")"

for port in "$port1" "$port2"; do
  sessions="$(http_get "$port" /metrics | sed -n 's/^hdof_sessions_total //p')"
  [[ "${sessions:-0}" -ge 1 ]] || fail "the daemon on port $port served no session"
  echo "daemon on port $port: $sessions sessions"
done
echo "test_proxy: passed"
