# Sourced by tests/deploy/test_shared_store.sh, test_replicas.sh and bench/store_rate.sh: a PostgreSQL from Debian's
# package in a temporary directory (as an unprivileged user when run as root), roomrender replicas on
# free loopback ports, and Debian's nginx with deploy/nginx/roomrender.conf in front of them.
# Needs: $work (a fresh temporary directory), $binary (roomrender), $source_dir; defines fail() first.

replica_pids=()
replica_ports=()
nginx_pid=""
nginx_port=""
pg_port=""
pg_bin="$(ls -d /usr/lib/postgresql/*/bin 2>/dev/null | sort -V | tail -1 || true)"

cluster_cleanup() {
  [ -n "$nginx_pid" ] && kill "$nginx_pid" 2>/dev/null
  for p in "${replica_pids[@]}"; do [ -n "$p" ] && kill "$p" 2>/dev/null; done
  [ -d "$work/pg/data" ] && pg_as_owner "$pg_bin/pg_ctl" -D "$work/pg/data" -m immediate stop >/dev/null 2>&1
  wait 2>/dev/null || true
}

free_port() {  # a port nothing listens on just now, below the kernel's ephemeral range (32768-)
  local port
  for port in $(shuf -i 20000-32000 -n 50); do
    (exec 3<>"/dev/tcp/127.0.0.1/$port") 2>/dev/null || { echo "$port"; return; }
  done
  fail "no free port"
}

# PostgreSQL refuses to run as root; CI runs as root, so the server runs as `nobody` there.
pg_as_owner() {
  if [ "$(id -u)" -eq 0 ]; then runuser -u nobody -- "$@"; else "$@"; fi
}

pg_init() {  # initdb with trust auth for the one local user `roomrender`, database `roomrender`
  chmod 711 "$work"
  mkdir -p "$work/pg"
  [ "$(id -u)" -eq 0 ] && chown nobody "$work/pg"
  pg_as_owner "$pg_bin/initdb" -D "$work/pg/data" -U roomrender -A trust -E UTF8 --no-locale \
    >"$work/pg/initdb.log" 2>&1 || fail "initdb: $(tail -5 "$work/pg/initdb.log")"
  pg_port=$(free_port)
  pg_start
  pg_as_owner "$pg_bin/createdb" -h 127.0.0.1 -p "$pg_port" -U roomrender roomrender \
    || fail "createdb failed"
  store_url="postgresql://roomrender@127.0.0.1:$pg_port/roomrender"
}

pg_reset_db() {  # an empty database `roomrender` again
  pg_as_owner "$pg_bin/dropdb" -h 127.0.0.1 -p "$pg_port" -U roomrender roomrender || fail "dropdb failed"
  pg_as_owner "$pg_bin/createdb" -h 127.0.0.1 -p "$pg_port" -U roomrender roomrender || fail "createdb failed"
}

pg_start() {
  pg_as_owner "$pg_bin/pg_ctl" -D "$work/pg/data" -l "$work/pg/server.log" -w -t 60 \
    -o "-c listen_addresses=127.0.0.1 -p $pg_port -c unix_socket_directories=$work/pg" start >/dev/null \
    || fail "PostgreSQL did not start: $(tail -5 "$work/pg/server.log")"
}

pg_stop() {
  pg_as_owner "$pg_bin/pg_ctl" -D "$work/pg/data" -m fast -w stop >/dev/null || fail "pg_ctl stop failed"
}

psql_value() {  # $1: SQL; prints the single value
  pg_as_owner "$pg_bin/psql" -h 127.0.0.1 -p "$pg_port" -U roomrender -d roomrender -XAtq -c "$1"
}

# Starts one replica with "$@" as extra serve arguments; appends its pid and port.
start_replica() {
  local n=$(( ${#replica_pids[@]} + 1 ))
  local log="$work/replica-$n.log"
  "$binary" serve --port 0 --bind 127.0.0.1 --log-requests 0 "$@" >"$log" 2>&1 &
  replica_pids+=($!)
  local port=""
  for _ in $(seq 1 200); do
    port=$(grep -o '"port":[0-9]*' "$log" 2>/dev/null | head -1 | cut -d: -f2 || true)
    [ -n "$port" ] && break
    kill -0 "${replica_pids[-1]}" 2>/dev/null || break
    sleep 0.05
  done
  [ -n "$port" ] || fail "replica $n did not start: $(tail -5 "$log")"
  replica_ports+=("$port")
}

kill_replica() {  # $1: index into replica_pids; SIGKILL, as a lost machine
  kill -KILL "${replica_pids[$1]}" 2>/dev/null || true
  wait "${replica_pids[$1]}" 2>/dev/null || true
  replica_pids[$1]=""
}

stop_replicas() {
  for p in "${replica_pids[@]}"; do [ -n "$p" ] && kill "$p" 2>/dev/null; done
  for p in "${replica_pids[@]}"; do [ -n "$p" ] && wait "$p" 2>/dev/null; done
  replica_pids=()
  replica_ports=()
}

# nginx with the shipped server block and an upstream of "$@" (loopback ports), hashed as the
# shipped upstream files hash.
start_nginx() { start_nginx_balanced 'hash $roomrender_affinity consistent;' "$@"; }

# The same with the upstream's balancing line $1 ("" = round robin) and the ports after it.
start_nginx_balanced() {
  local balance="$1"
  shift
  [ -n "$nginx_port" ] || nginx_port=$(free_port)
  {
    echo "worker_processes 1; daemon off; pid $work/nginx.pid; error_log $work/error.log warn;"
    echo "events { worker_connections 512; }"
    echo "http {"
    echo "  access_log off;"
    for t in client_body proxy fastcgi uwsgi scgi; do echo "  ${t}_temp_path $work/$t;"; done
    echo "  upstream roomrender {"
    [ -n "$balance" ] && echo "    $balance"
    for p in "$@"; do echo "    server 127.0.0.1:$p max_fails=1 fail_timeout=5s;"; done
    echo "    keepalive 16;"
    echo "  }"
    sed -e "s|^  listen 8080;|  listen 127.0.0.1:$nginx_port;|" "$source_dir/deploy/nginx/roomrender.conf" | sed 's/^/  /'
    echo "}"
  } >"$work/nginx.conf"
  nginx -t -q -c "$work/nginx.conf" -p "$work" 2>"$work/nginx-t.log" || fail "nginx -t: $(cat "$work/nginx-t.log")"
  nginx -c "$work/nginx.conf" -p "$work" &
  nginx_pid=$!
  for _ in $(seq 1 200); do
    curl -sf "http://127.0.0.1:$nginx_port/livez" >/dev/null 2>&1 && return
    kill -0 "$nginx_pid" 2>/dev/null || break
    sleep 0.05
  done
  fail "nginx did not come up on port $nginx_port"
}

stop_nginx() { kill "$nginx_pid" 2>/dev/null || true; wait "$nginx_pid" 2>/dev/null || true; nginx_pid=""; }

live_ports() {  # the ports of replicas not killed
  local i
  for i in "${!replica_pids[@]}"; do [ -n "${replica_pids[$i]}" ] && echo "${replica_ports[$i]}"; done
}
