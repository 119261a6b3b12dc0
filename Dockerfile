# Multi-stage build of `patchwork`; the image runs the HTTP service.
#
#   docker build -t patchwork .
#   docker run -p 8080:8080 -v patchwork-data:/data -e PATCHWORK_API_KEYS=secret patchwork
#
# The database lives on the /data volume, so jobs survive container restarts
# (running jobs resume from their checkpoints).

FROM rust:1.95-slim-bookworm AS build
WORKDIR /src
# Dependencies first, so code changes do not rebuild them.
COPY Cargo.toml Cargo.lock ./
COPY crates/patchwork-core/Cargo.toml crates/patchwork-core/Cargo.toml
RUN mkdir -p src crates/patchwork-core/src crates/patchwork-core/benches benches \
    && echo 'fn main() {}' > src/main.rs \
    && touch crates/patchwork-core/src/lib.rs \
    && for b in curve_ksa forward; do echo 'fn main() {}' > crates/patchwork-core/benches/$b.rs; done \
    && echo 'fn main() {}' > benches/service_load.rs \
    && cargo build --release --locked --bin patchwork \
    && rm -rf src crates/patchwork-core/src
COPY . .
# Touch the sources so cargo rebuilds them over the placeholders.
RUN touch src/main.rs crates/patchwork-core/src/lib.rs \
    && cargo build --release --locked --bin patchwork

FROM debian:bookworm-slim
RUN apt-get update \
    && apt-get install -y --no-install-recommends ca-certificates curl \
    && rm -rf /var/lib/apt/lists/* \
    && useradd --system --create-home --home-dir /home/patchwork patchwork \
    && mkdir /data && chown patchwork:patchwork /data
COPY --from=build /src/target/release/patchwork /usr/local/bin/patchwork
USER patchwork
WORKDIR /data
VOLUME ["/data"]
EXPOSE 8080
HEALTHCHECK --interval=30s --timeout=3s --start-period=10s --retries=3 \
    CMD curl -fsS http://127.0.0.1:8080/healthz || exit 1
# SIGTERM checkpoints running jobs before the process exits.
STOPSIGNAL SIGTERM
ENTRYPOINT ["patchwork"]
CMD ["serve", "--addr", "0.0.0.0:8080", "--db", "/data/patchwork.db"]
