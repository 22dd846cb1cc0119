# Every target does its own install steps, so a fresh clone needs only `make demo` or `make test`.
PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
export MPLBACKEND := Agg

.PHONY: install demo test test-rust test-python clean

$(VENV)/.created:
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip "maturin>=1.5,<2"
	touch $@

# Builds the Rust extension in release mode and installs axmpm (editable) with its test extras,
# again only when what the build reads changed: the crates, Cargo.lock or pyproject.toml (the
# Python sources are installed editable, so editing them needs no reinstall), or the built
# extension is gone. The build's and pip's output go to $(VENV)/install.log, shown only when the
# install fails. `make -B install` forces it.
INSTALLED := $(VENV)/.installed
BUILD_INPUTS := Cargo.toml Cargo.lock pyproject.toml \
	$(shell find crates -name '*.rs' -o -name Cargo.toml -o -name build.rs)
ifeq ($(wildcard python/axmpm/_core*.so),)
.PHONY: $(INSTALLED)
endif

$(INSTALLED): $(VENV)/.created $(BUILD_INPUTS)
	@echo "building the engine and installing axmpm into $(VENV) (a few minutes on a fresh clone; log: $(VENV)/install.log)"
	@VIRTUAL_ENV=$(abspath $(VENV)) PATH=$(abspath $(VENV))/bin:$$PATH \
	  $(VENV)/bin/maturin develop --release --extras test > $(VENV)/install.log 2>&1 \
	  || { cat $(VENV)/install.log; echo "error: the install failed (log above, also in $(VENV)/install.log)"; exit 1; }
	@touch $@

install: $(INSTALLED)

demo: install
	$(VENV)/bin/axmpm demo --out runs/demo --overwrite

test-rust:
	cargo test --release -p axmpm-core

test-python: install
	$(VENV)/bin/python -m pytest -q

test: install test-rust test-python

clean:
	rm -rf $(VENV) target runs
