# Multi-stage build of the `patchwork` binary.
# Today the image runs the CLI; the HTTP service (`patchwork serve`, with its
# port, database volume and HEALTHCHECK) arrives with the service issue.
FROM rust:1.95-slim-bookworm AS build
WORKDIR /src
COPY . .
RUN cargo build --release --locked --bin patchwork

FROM debian:bookworm-slim
RUN useradd --system --create-home --home-dir /home/patchwork patchwork
COPY --from=build /src/target/release/patchwork /usr/local/bin/patchwork
USER patchwork
WORKDIR /home/patchwork
ENTRYPOINT ["patchwork"]
CMD ["--help"]
