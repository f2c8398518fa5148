# The two commands of the README, and a few helpers. Each target installs what it needs first
# (scripts/install-deps.sh is idempotent and quick when everything is present).
BUILD ?= build
MESON_FLAGS ?=

.PHONY: all deps build demo test format clean

all: build

deps:
	@bash scripts/install-deps.sh

$(BUILD)/build.ninja:
	meson setup $(BUILD) $(MESON_FLAGS)

build: deps $(BUILD)/build.ninja
	ninja -C $(BUILD)

demo: build
	bash scripts/demo.sh $(BUILD)

test: build
	meson test -C $(BUILD) --print-errorlogs --num-processes 2 -t 4

format: deps
	git ls-files '*.cpp' '*.hpp' | xargs clang-format -i

clean:
	rm -rf $(BUILD) out
