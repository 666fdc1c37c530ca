# rfesim HTTP service: docker build -t rfesim . && docker run -p 8000:8000 -v rfesim-data:/data rfesim
FROM python:3.11-slim

ENV PYTHONDONTWRITEBYTECODE=1 \
    PYTHONUNBUFFERED=1 \
    PIP_NO_CACHE_DIR=1 \
    PIP_DISABLE_PIP_VERSION_CHECK=1 \
    NUMBA_CACHE_DIR=/home/rfesim/.cache/numba \
    RFESIM_DATA_DIR=/data \
    RFESIM_SCENARIOS_DIR=/app/scenarios

# install the package with the service extra (FastAPI, uvicorn, Dask), keep only the
# example scenarios: the source tree is not left where `import rfesim` could find it
COPY . /src
RUN pip install "/src[service]" \
    && mkdir -p /app \
    && cp -r /src/scenarios /app/scenarios \
    && rm -rf /src

RUN useradd --create-home --uid 10001 rfesim \
    && mkdir -p /data \
    && chown rfesim:rfesim /data
USER rfesim
WORKDIR /app

# compile the numba kernels once, into the image, in parallel processes (the workers then only
# load them)
RUN python -c "import rfesim; rfesim.precompile()" \
    && python -c "import rfesim; rfesim.simulate('scenarios/cantilever_pipe.json')" \
    && python -c "from service.worker import warm_up; warm_up()"

VOLUME /data
EXPOSE 8000
HEALTHCHECK --interval=30s --timeout=5s --start-period=60s \
    CMD python -c "import urllib.request; urllib.request.urlopen('http://127.0.0.1:8000/health', timeout=4)"
CMD ["rfesim", "serve", "--host", "0.0.0.0", "--port", "8000"]
