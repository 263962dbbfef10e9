# Sourced by the benchmark scripts: a PostgreSQL server of its own on a temporary folder and a
# free loopback port (initdb + pg_ctl from Debian's postgresql-15, trust authentication, fsync on).
#   start_temp_postgres DIR   starts it in DIR/pg and sets PG_URI_BASE (postgresql://fleetnav@127.0.0.1:PORT)
#   new_temp_database NAME    creates database NAME and prints its URI
#   temp_psql NAME SQL        runs SQL on database NAME, unaligned output without headers
#   stop_temp_postgres [DIR]  stops it (safe to call when it never started); with DIR, the one
#                             started in DIR by another shell
pg_ctl_as=()
pg_dir=""
start_temp_postgres() {
  local dir=$1
  pg_bin=$(ls -d /usr/lib/postgresql/*/bin | sort -V | tail -1)
  [ "$(id -u)" -eq 0 ] && { chown postgres "$dir"; pg_ctl_as=(runuser -u postgres --); }
  pg_port=$(/usr/bin/python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
  pg_dir="$dir/pg"
  "${pg_ctl_as[@]}" "$pg_bin/initdb" -D "$pg_dir" -U fleetnav --auth=trust -E UTF8 >/dev/null
  "${pg_ctl_as[@]}" "$pg_bin/pg_ctl" -D "$pg_dir" -l "$dir/pg.log" -w \
    -o "-p $pg_port -k $dir -c listen_addresses=127.0.0.1" start >/dev/null
  PG_URI_BASE="postgresql://fleetnav@127.0.0.1:$pg_port"
}
new_temp_database() {
  "${pg_ctl_as[@]}" "$pg_bin/createdb" -h 127.0.0.1 -p "$pg_port" -U fleetnav "$1"
  echo "$PG_URI_BASE/$1"
}
temp_psql() {
  "$pg_bin/psql" -h 127.0.0.1 -p "$pg_port" -U fleetnav -d "$1" -At -c "$2"
}
stop_temp_postgres() {
  local dir=${1:+$1/pg}
  dir=${dir:-$pg_dir}
  [ -n "$dir" ] || return 0
  local bin as=()
  bin=$(ls -d /usr/lib/postgresql/*/bin | sort -V | tail -1)
  [ "$(id -u)" -eq 0 ] && as=(runuser -u postgres --)
  "${as[@]}" "$bin/pg_ctl" -D "$dir" -m fast stop >/dev/null 2>&1
  return 0
}
