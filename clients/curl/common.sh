# Sourced by the examples: the server's base URL and curl flags shared by all of them.
#   ROOMRENDER_URL   the server (default http://127.0.0.1:8080)
# --fail-with-body: an error answer (problem+json: detail and {pointer, detail} per field) is
# printed and the script stops with curl's exit status 22.
ROOMRENDER_URL="${ROOMRENDER_URL:-http://127.0.0.1:8080}"
ROOMRENDER_URL="${ROOMRENDER_URL%/}"
curl_rr() {
  curl --silent --show-error --fail-with-body "$@"
}
