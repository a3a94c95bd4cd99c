# Thin wrapper over CMake. `make demo` and `make test` do all the set-up on Debian 12.
BUILD    ?= build
JOBS     ?= $(shell nproc)
PACKAGES := cmake g++ make pkg-config libglm-dev libopenmesh-dev libembree-dev libtbb-dev \
            nlohmann-json3-dev libcli11-dev libstb-dev libgtest-dev libgmock-dev \
            glslang-dev glslang-tools spirv-tools libvulkan-dev mesa-vulkan-drivers \
            vulkan-validationlayers vulkan-tools clang-format
# Only the tests need these: the --report test renders the page in a headless browser.
TEST_PACKAGES := chromium
SUDO     := $(shell [ "$$(id -u)" = 0 ] || echo sudo)

.PHONY: all deps test-deps configure build demo test bundle clean format format-check

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

test-deps:
	$(call install_missing,$(TEST_PACKAGES))

$(BUILD)/CMakeCache.txt: | deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo

configure: deps $(BUILD)/CMakeCache.txt

build: configure
	cmake --build $(BUILD) -j $(JOBS)

demo: build
	@mkdir -p out
	$(BUILD)/cli/stsv render fence -o out/fence.png --visibility out/fence_visibility.png
	@echo "wrote out/fence.png"

test: build test-deps
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

# dist/stsv-VERSION-linux-ARCH.tar.gz: the program with its shared libraries (cmake/Bundle.cmake).
bundle: build
	cmake -DBUILD_DIR=$(BUILD) -DOUTPUT_DIR=dist -P cmake/Bundle.cmake

format:
	git ls-files '*.cpp' '*.h' | xargs clang-format -i

# Fails on any tracked C++ file that `make format` would change (CI runs it).
format-check: deps
	git ls-files '*.cpp' '*.h' | xargs clang-format --dry-run -Werror

clean:
	rm -rf $(BUILD) out dist
