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

# Builds the Rust extension in release mode and installs axmpm (editable) with its test extras.
install: $(VENV)/.created
	VIRTUAL_ENV=$(abspath $(VENV)) PATH=$(abspath $(VENV))/bin:$$PATH \
	  $(VENV)/bin/maturin develop --release --quiet --extras test

demo: install
	$(VENV)/bin/axmpm demo --out runs/demo --overwrite

test-rust:
	cargo test --release -p axmpm-core

test-python: install
	$(VENV)/bin/python -m pytest -q

test: install test-rust test-python

clean:
	rm -rf $(VENV) target runs
