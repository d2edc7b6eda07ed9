# A service image made of one Debian package, for compose.yaml: Redis and HAProxy from
# Debian 12 (built locally like meshd's image: no registry needed, see docker/build.sh).
#   podman build --format docker --build-arg PACKAGE=redis-server -f docker/debian-package.Dockerfile .
FROM debian:bookworm
ARG PACKAGE
RUN apt-get update -qq \
 && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "$PACKAGE" \
 && rm -rf /var/lib/apt/lists/* /var/cache/apt/*
