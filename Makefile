# inkbsdf — two commands on a fresh machine: `make demo` and `make test`.
SHELL := /bin/bash
PY    ?= python3
VENV  := .venv
VPY   := $(VENV)/bin/python
STAMP := $(VENV)/.installed
LLVM_STAMP := $(VENV)/.llvm-ok
# Demo / test settings (override on the command line, e.g. `make demo SPP=256`).
SPP   ?= 64
OUT   ?= out

.PHONY: all demo test bench llvm venv tables clean

all: demo

# ---------------------------------------------------------------- bootstrap
$(STAMP): pyproject.toml
	@test -x $(VPY) || $(PY) -m venv $(VENV)
	$(VPY) -m pip install --quiet --upgrade pip
	$(VPY) -m pip install --quiet -e ".[test]"
	@touch $@

venv: $(STAMP)

# Mitsuba's LLVM variants need libLLVM >= 16 (Debian 12 ships 15, which crashes
# in JIT code with "Cannot select: fminimum").  Install libllvm19 with apt when
# we can, otherwise stop with a clear message.
$(LLVM_STAMP): $(STAMP)
	@if ! ldconfig -p | grep -Eq 'libLLVM(-|\.so\.)(1[6-9]|[2-9][0-9])'; then \
	  if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
	    echo "libLLVM >= 16 not found: installing libllvm19 with apt-get"; \
	    (apt-get install -y libllvm19 >/dev/null 2>&1 || \
	     (apt-get update >/dev/null 2>&1 && apt-get install -y libllvm19 >/dev/null)) || \
	     { echo "ERROR: apt-get install libllvm19 failed"; exit 1; }; \
	  else \
	    echo "ERROR: Mitsuba's LLVM backend needs libLLVM >= 16 (found none)."; \
	    echo "       Install it (Debian/Ubuntu: 'sudo apt-get install libllvm19')"; \
	    echo "       or point DRJIT_LIBLLVM_PATH at a libLLVM.so of version 16 or newer."; \
	    exit 1; \
	  fi; \
	fi
	@$(VPY) -m inkbsdf.check_backend
	@touch $@

llvm: $(LLVM_STAMP)

# ------------------------------------------------------------------- targets
TABLE_DIR := $(OUT)/tables

# the demo inks (inkbsdf/apps/demo_tables.py): missing or unreadable tables are (re)built
tables: $(LLVM_STAMP)
	@$(VPY) -m inkbsdf.apps.demo_tables $(TABLE_DIR)

demo: tables
	$(VPY) -m inkbsdf.render scenes/printed_page.xml --tables $(TABLE_DIR) \
	    --spp $(SPP) -o $(OUT)/printed_page.exr --png $(OUT)/printed_page.png

test: $(LLVM_STAMP)
	$(VPY) -m pytest -q tests

bench: $(LLVM_STAMP)
	$(VPY) -m benchmarks

clean:
	rm -rf $(OUT) .pytest_cache
