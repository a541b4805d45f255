# One image for every armplan process: the services (fit, decide, ik, timing,
# planner), the bridge, the recorder and the simulated NAO. docker-compose.yml
# picks the process with `command:`; the Zenoh router is the eclipse/zenoh
# image. Build: docker build -t armplan .   Details: docs/services.md.
FROM python:3.11-slim

# The user the processes run as; match it to the owner of bind-mounted files
# (the certificates of docker-compose.secure.yml), e.g. --build-arg ARMPLAN_UID=$(id -u).
# Never 0: a root shell's id -u would make that user root (useradd refuses it).
ARG ARMPLAN_UID=1000
RUN test "${ARMPLAN_UID}" != 0 || { echo "ARMPLAN_UID is 0 (id -u of a root shell): the processes do not run as root; build without --build-arg ARMPLAN_UID (uid 1000) and give the bundle to that user: chown -R 1000 secure-compose" >&2; exit 1; }

ENV PYTHONDONTWRITEBYTECODE=1 \
    PYTHONUNBUFFERED=1 \
    PIP_NO_CACHE_DIR=1 \
    PIP_DISABLE_PIP_VERSION_CHECK=1

WORKDIR /opt/armplan

# Dependencies first, pinned by constraints.txt, so that a change to the code
# does not reinstall them: install the project's metadata with an empty
# package tree, then the code itself without dependencies.
COPY pyproject.toml setup.py constraints.txt README.md ./
COPY armplan/__init__.py armplan/__init__.py
RUN pip install -c constraints.txt . && pip uninstall --yes armplan

COPY armplan armplan
COPY shared shared
COPY services services
COPY bridge bridge
COPY config config
# The IK's hot loop is compiled with mypyc (setup.py, shared/compiled.py): a C
# compiler is there for the build only and removed in the same layer.
RUN apt-get update \
    && apt-get install --yes --no-install-recommends gcc libc6-dev \
    && pip install --no-deps -c constraints.txt . \
    && apt-get purge --yes --auto-remove gcc libc6-dev \
    && rm -rf /var/lib/apt/lists/* \
    && useradd --uid "${ARMPLAN_UID}" --create-home --shell /usr/sbin/nologin armplan \
    && mkdir -p /recordings /var/lib/armplan/fit \
    && chown armplan /recordings /var/lib/armplan/fit

# Every armplan process reads this Zenoh configuration: the router is the
# compose service `router` (docker-compose.secure.yml points each process at
# its own TLS and user/password file instead).
ENV ARMPLAN_ZENOH_CONFIG=/opt/armplan/config/compose.json5

USER armplan
# Out of the source tree, so `python -m ...` runs the installed packages.
WORKDIR /recordings
CMD ["armplan", "--help"]
