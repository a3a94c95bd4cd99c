# Thin wrapper over CMake. `make demo` and `make test` do all the set-up on Debian 12.
BUILD    ?= build
JOBS     ?= $(shell nproc)
PACKAGES := cmake g++ make pkg-config libglm-dev libopenmesh-dev libembree-dev libtbb-dev libopenexr-dev \
            nlohmann-json3-dev libcli11-dev libstb-dev libgtest-dev libgmock-dev libtinygltf-dev \
            glslang-dev glslang-tools spirv-tools libvulkan-dev mesa-vulkan-drivers \
            vulkan-validationlayers vulkan-tools clang-format
# Only the tests need these: the --report test renders the page in a headless browser,
# bench/tables.py (the measurement tables, checked by the suite) is Python, and the EXR test reads
# the files back with OpenEXR's own exrheader; the glTF tests read Khronos's sample models from
# assimp's test data.
TEST_PACKAGES := chromium python3 openexr assimp-testmodels
# make fuzz: libFuzzer harnesses of the loaders (tests/fuzz), built with clang.
FUZZ_PACKAGES := clang-14 libfuzzer-14-dev
FUZZ_BUILD    ?= build-fuzz
FUZZ_SECONDS  ?= 60
FUZZ_TARGETS  := json obj off png npy exr gltf
# make sanitize: everything that runs on the CPU under AddressSanitizer and UBSan, with GCC's
# float-cast-overflow check (a NaN or an infinity converted to an integer), which its `undefined`
# group leaves out. Debug information is line tables only (-g1): the reports' stacks keep their
# files and lines, and the build takes a third less time than with -g (measured on
# cli/bench_command.cpp: 47 s against 29 s).
SANITIZE_BUILD ?= build-asan
SANITIZE_FLAGS := -O1 -fsanitize=address,undefined,float-cast-overflow -fno-sanitize=vptr \
                  -fno-sanitize-recover=undefined,float-cast-overflow -fno-omit-frame-pointer
SANITIZE_TESTS := core scene sampling volumes shadowmaps wedges render reference fuzz
# The suites that load the Vulkan driver run with leak detection off: lavapipe and the validation
# layer, loaded with dlopen and not built with ASan, leave allocations LeakSanitizer reports.
SANITIZE_GPU_TESTS := gpu gpu_render cli
# Left out: the test that runs every command of the docs (ten minutes uninstrumented; the cli
# suite's own tests run the same commands' code), and the one that runs stsv out of address space
# to see it refuse: ASan's own allocator, which reserves its shadow memory up front, aborts there.
SANITIZE_EXCLUDE := ^DocsCommands\.|^TrustValues\.OutOfMemoryWhileReadingTheArguments
# make lint: clang-tidy (.clang-tidy; tests/.clang-tidy for the tests) over every translation
# unit of the build that is part of the checkout, and through them every project header; the
# sources the build generates are left out. LINT_FILES narrows it (a regular expression over the
# files' absolute paths).
LINT_PACKAGES := clang-tidy-14
LINT_FILES    ?= ^$(CURDIR)/(?!$(BUILD)/)
SUDO     := $(shell [ "$$(id -u)" = 0 ] || echo sudo)

.PHONY: all deps test-deps configure build demo test bundle clean format format-check fuzz fuzz-deps sanitize \
        lint lint-deps

all: build

# $(call install_missing,PACKAGES): installs only what is missing; a no-op when everything is there.
define install_missing
	@missing=$$(for p in $(1); do dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q '^install ok installed' || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  echo "installing:" $$missing; \
	  $(SUDO) apt-get update -qq && DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq --no-install-recommends $$missing; \
	fi
endef

deps:
	$(call install_missing,$(PACKAGES))

# The mesh-shader tests run on a second lavapipe, fetched into the build folder without touching
# the system's Vulkan (tests/drivers/fetch_lavapipe.sh); where it cannot be fetched, their ctest
# entry fails and says why.
test-deps:
	$(call install_missing,$(TEST_PACKAGES))
	@bash tests/drivers/fetch_lavapipe.sh $(BUILD)/drivers/lavapipe-backports || \
	  echo "warning: the second lavapipe could not be fetched; mesh_shaders.lavapipe_backports will fail"
	@bash bench/fetch_meshes.sh build/meshes || \
	  echo "warning: the real meshes could not be fetched; the docs' real-meshes commands will fail"

$(BUILD)/CMakeCache.txt: | deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo

configure: deps $(BUILD)/CMakeCache.txt

build: configure
	cmake --build $(BUILD) -j $(JOBS)

# The demo: the chain-link fence's shadow, sharp at its foot and softening away from it (STSV
# paper Fig. 1): coarse tiles and a half-metre light, 2x2 visible points per pixel.
DEMO_OPTIONS := --set repeat=4 --set light_size=0.5 --supersample 2 --size 768x576
demo: build
	@mkdir -p out
	$(BUILD)/cli/stsv render fence $(DEMO_OPTIONS) -o out/fence.png --visibility out/fence_visibility.png
	@echo "wrote out/fence.png"

test: build test-deps
	cd $(BUILD) && ctest --output-on-failure --no-tests=error -j $(JOBS)

fuzz-deps:
	$(call install_missing,$(FUZZ_PACKAGES))

# Each loader's fuzzer for FUZZ_SECONDS (default 60); fails on a crash, leak or timeout.
fuzz: deps fuzz-deps
	cmake -S . -B $(FUZZ_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++-14 \
	  -DSTSV_FUZZ=ON -DSTSV_WERROR=OFF \
	  -DCMAKE_CXX_FLAGS="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined"
	cmake --build $(FUZZ_BUILD) -j $(JOBS) --target $(addprefix fuzz_,$(FUZZ_TARGETS))
	bash tests/fuzz/run.sh $(FUZZ_BUILD) $(FUZZ_SECONDS) $(FUZZ_TARGETS)

# Every suite that runs on the CPU under ASan and UBSan (SANITIZE_*). UBSan's vptr check is off:
# it needs the RTTI of glslang's classes, which Debian builds without. Each label must select a
# test: `ctest -L` with a label that matches nothing passes, so a renamed suite would empty a stage.
sanitize: deps test-deps
	cmake -S . -B $(SANITIZE_BUILD) -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG=-g1 -DSTSV_WERROR=OFF \
	  -DCMAKE_CXX_FLAGS="$(SANITIZE_FLAGS)"
	cmake --build $(SANITIZE_BUILD) -j $(JOBS) --target $(addprefix test_,$(SANITIZE_TESTS) $(SANITIZE_GPU_TESTS))
	@cd $(SANITIZE_BUILD) && for label in $(SANITIZE_TESTS) $(SANITIZE_GPU_TESTS); do \
	  ctest -N -L "^$$label$$" | grep -q 'Total Tests: [1-9]' || { echo "make sanitize: label $$label selects no test" >&2; exit 1; }; \
	done
	cd $(SANITIZE_BUILD) && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
	  ctest --output-on-failure --no-tests=error -j $(JOBS) -L '^($(subst $(eval) ,|,$(SANITIZE_TESTS)))$$'
	cd $(SANITIZE_BUILD) && ASAN_OPTIONS=detect_leaks=0 UBSAN_OPTIONS=print_stacktrace=1 \
	  ctest --output-on-failure --no-tests=error -j $(JOBS) -L '^($(subst $(eval) ,|,$(SANITIZE_GPU_TESTS)))$$' \
	  -E '$(SANITIZE_EXCLUDE)'

# dist/stsv-VERSION-linux-ARCH.tar.gz: the program with its shared libraries (cmake/Bundle.cmake).
bundle: build
	cmake -DBUILD_DIR=$(BUILD) -DOUTPUT_DIR=dist -P cmake/Bundle.cmake

format:
	git ls-files '*.cpp' '*.h' | xargs clang-format -i

# Fails on any tracked C++ file that `make format` would change (CI runs it).
format-check: deps
	git ls-files '*.cpp' '*.h' | xargs clang-format --dry-run -Werror

lint-deps:
	$(call install_missing,$(LINT_PACKAGES))

# Fails on any finding (warnings are errors); about 15 minutes on two cores for the whole tree.
lint: configure lint-deps
	run-clang-tidy-14 -p $(BUILD) -j $(JOBS) -quiet -extra-arg=-Wno-unknown-warning-option '$(LINT_FILES)'

clean:
	rm -rf $(BUILD) $(FUZZ_BUILD) $(SANITIZE_BUILD) out dist
