# The whole package on any machine with a container runtime: the ROS 2 Jazzy wheels on PyPI are
# Linux x86_64 only, so on macOS (Apple Silicon too, through amd64 emulation), Windows and ARM
# Linux this image is the way in. doc/install.md says how to build and run it. The build's only
# set-up step is scripts/setup_system.sh, which `make fresh-linux` tests on fresh Debian roots.
FROM --platform=linux/amd64 debian:bookworm-slim

WORKDIR /simple_robot_control
COPY scripts/check_system.sh scripts/setup_system.sh scripts/
RUN scripts/setup_system.sh && rm -rf /var/lib/apt/lists/*
COPY . .
RUN make install
ENV PATH=/simple_robot_control/.venv/bin:$PATH

# foxglove_live serves on the container's own interface only when asked (FOXGLOVE_HOST=0.0.0.0);
# publish it to the host's loopback alone: docker run -p 127.0.0.1:8765:8765 ...
EXPOSE 8765
CMD ["make", "demo"]
