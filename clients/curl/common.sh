# Sourced by the examples: the server's base URL and curl helpers shared by all of them.
#   ROOMRENDER_URL   the server (default http://127.0.0.1:8080)
# On an error answer (problem+json: a detail and {pointer, detail} per field) the helpers print the
# problem on stderr and the script stops with curl's exit status (22).
ROOMRENDER_URL="${ROOMRENDER_URL:-http://127.0.0.1:8080}"
ROOMRENDER_URL="${ROOMRENDER_URL%/}"

curl_rr() {
  curl --silent --show-error --fail-with-body "$@"
}

# fetch_to FILE CURL_ARGS...: the answer's body into FILE; an error's body (the problem) to stderr.
fetch_to() {
  local file="$1"
  shift
  local status=0
  curl_rr -o "$file" "$@" || status=$?
  if [ "$status" -ne 0 ]; then
    [ -f "$file" ] && cat "$file" >&2 && echo >&2
    rm -f "$file"
    return "$status"
  fi
}
