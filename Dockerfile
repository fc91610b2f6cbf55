# roomrender as a container. Two stages on Debian 12:
#   build    installs the build packages (scripts/install-deps.sh build), compiles with -Werror and
#            runs the unit tests, in two shards side by side, so a broken build never yields an image
#            (all but the one that holds docs/api.md to the settings table: .dockerignore keeps docs
#            out of the context);
#   runtime  only the binary, its shared libraries (from Debian's packages), the web page, the
#            examples, the schemas and the furniture catalogue (CC BY 3.0), run as an unprivileged user (uid 10001) that owns the data
#            directory /var/lib/roomrender (a VOLUME: stored scenes survive restarts).
# The build stage copies the whole build context, so a new source folder needs no change here;
# .dockerignore keeps build trees, node_modules, .git and test outputs out of it.
# Configuration is by environment variable (ROOMRENDER_PORT, ROOMRENDER_BIND, ROOMRENDER_THREADS, ...;
# see `roomrender serve --help`); SIGTERM drains in-flight renders and exits 0.
# Checked without a Docker engine by scripts/container-check.sh (podman/buildah, chroot isolation).

FROM docker.io/library/debian:bookworm AS build
COPY scripts/install-deps.sh /tmp/install-deps.sh
RUN /tmp/install-deps.sh build && rm -rf /var/lib/apt/lists/*
WORKDIR /src
COPY . .
RUN cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DROOMRENDER_WERROR=ON -DROOMRENDER_BENCH=OFF \
 && cmake --build build -j"$(nproc)" --target roomrender unit_tests \
 && export GTEST_BRIEF=1 GTEST_FILTER=-ServerSettings.DocsApiTableHasEveryRowWithItsVariableDefaultAndUnit GTEST_TOTAL_SHARDS=2 \
 && (GTEST_SHARD_INDEX=0 build/tests/unit_tests & first=$!; \
     GTEST_SHARD_INDEX=1 build/tests/unit_tests; second=$?; wait "$first" && [ "$second" -eq 0 ])

FROM docker.io/library/debian:bookworm AS runtime
# libcpp-httplib0.11 pulls in OpenSSL, zlib and brotli; pugixml and libzip read Sweet Home 3D files;
# libpq5 talks to the shared store (--store postgresql://...); libpng16-16 and libturbojpeg0 decode
# textures.
RUN apt-get update \
 && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends libcpp-httplib0.11 zlib1g libpugixml1v5 libzip4 libpq5 libpng16-16 libturbojpeg0 \
 && rm -rf /var/lib/apt/lists/* /var/cache/apt/* /var/log/apt /var/log/dpkg.log \
 && groupadd --system --gid 10001 roomrender \
 && useradd --system --uid 10001 --gid 10001 --no-create-home --shell /usr/sbin/nologin roomrender \
 && install -d -o roomrender -g roomrender -m 0750 /var/lib/roomrender
COPY --from=build /src/build/roomrender /usr/local/bin/roomrender
COPY --from=build /src/clients/web /usr/share/roomrender/web
COPY --from=build /src/examples /usr/share/roomrender/examples
COPY --from=build /src/schemas /usr/share/roomrender/schemas
COPY --from=build /src/catalogue /usr/share/roomrender/catalogue
COPY --from=build /src/LICENSE /usr/share/doc/roomrender/LICENSE
ENV ROOMRENDER_PORT=8080 \
    ROOMRENDER_BIND=0.0.0.0 \
    ROOMRENDER_WEB_DIR=/usr/share/roomrender/web \
    ROOMRENDER_EXAMPLES_DIR=/usr/share/roomrender/examples \
    ROOMRENDER_SCHEMAS_DIR=/usr/share/roomrender/schemas \
    ROOMRENDER_CATALOGUE_DIR=/usr/share/roomrender/catalogue \
    ROOMRENDER_DATA_DIR=/var/lib/roomrender
# Declared after the directory is made and chowned: a new named volume mounted here starts as a copy
# of it, so it belongs to uid 10001 too (Kubernetes gets the same from fsGroup: 10001).
VOLUME /var/lib/roomrender
USER roomrender
EXPOSE 8080
# bash's /dev/tcp keeps curl (and its dozen libraries) out of the image.
HEALTHCHECK --interval=15s --timeout=3s --start-period=5s --retries=3 \
  CMD ["bash", "-c", "exec 3<>/dev/tcp/127.0.0.1/${ROOMRENDER_PORT} && printf 'GET /livez HTTP/1.0\\r\\n\\r\\n' >&3 && head -n1 <&3 | grep -q ' 200 '"]
STOPSIGNAL SIGTERM
ENTRYPOINT ["/usr/local/bin/roomrender"]
CMD ["serve"]
