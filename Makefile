# scotopia — the two set-up commands are `make demo` and `make test`.
SHELL := /bin/bash
.SHELLFLAGS := -eu -o pipefail -c

VENV      := .venv
PY        := $(VENV)/bin/python
STAMP     := $(VENV)/.installed
CARGO     ?= cargo
BIN       := target/release/scotopia
DEMO_OUT  := out/demo

.PHONY: all test demo gallery lighting bench tables fmt lint cargo-test python pytest toolchain clean fuzz browser binary

all: test

## The Python virtual environment with the build tool and the oracle.
$(STAMP): python/requirements-dev.txt
	python3 -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -r python/requirements-dev.txt
	touch $(STAMP)

## rustfmt and clippy, if the toolchain lacks them.
toolchain:
	@command -v rustup >/dev/null && rustup component add rustfmt clippy >/dev/null 2>&1 || true

fmt: toolchain
	$(CARGO) fmt --all -- --check

lint: toolchain
	$(CARGO) clippy --workspace --all-targets -- -D warnings

cargo-test:
	$(CARGO) test --workspace

## Builds the extension module into the venv (release: the tests are numeric).
python: $(STAMP)
	VIRTUAL_ENV=$(CURDIR)/$(VENV) PATH=$(CURDIR)/$(VENV)/bin:$$PATH \
	  $(VENV)/bin/maturin develop --release --quiet -m python/Cargo.toml

## The release binary: test_view_browser runs `scotopia view` from it.
binary:
	$(CARGO) build --release -p scotopia

## Debian's Chromium for test_view_browser, which drives it with Playwright
## (from requirements-dev.txt; Playwright's own browser download is not
## reachable, so `playwright install` is never run). Installed with apt-get
## when missing, as root or with passwordless sudo. Where it cannot be, this
## says so and goes on: the browser tests then fail, saying how to install it.
CHROMIUM := /usr/bin/chromium

browser:
	@if [ -x $(CHROMIUM) ]; then exit 0; fi; \
	fail() { echo "make browser: $$1: the browser tests will fail (install Debian's chromium: apt-get install chromium)" >&2; exit 0; }; \
	command -v apt-get >/dev/null || fail "$(CHROMIUM) is missing and there is no apt-get"; \
	if [ "$$(id -u)" = 0 ]; then sudo=; elif sudo -n true 2>/dev/null; then sudo="sudo -n"; \
	else fail "$(CHROMIUM) is missing and apt-get needs root or passwordless sudo"; fi; \
	echo "make browser: apt-get install chromium"; \
	export DEBIAN_FRONTEND=noninteractive; \
	$$sudo apt-get install -y -q chromium >/dev/null 2>&1 \
	  || { $$sudo apt-get update -q >/dev/null && $$sudo apt-get install -y -q chromium >/dev/null; } \
	  || fail "apt-get could not install chromium"; \
	[ -x $(CHROMIUM) ] || fail "apt-get installed chromium but $(CHROMIUM) is missing"

pytest: python browser binary
	$(PY) -m pytest -q python/tests

## The seeded fuzz tests at length: every input format through the CLI
## (make test runs 40 mutations per input; this runs 5000) and every
## Python entry point (make test: 25 calls each; this: 2000).
fuzz: python
	SCOTOPIA_FUZZ_CASES=5000 $(CARGO) test -p scotopia --test fuzz_cli -- --nocapture
	SCOTOPIA_FUZZ_CASES=2000 $(PY) -m pytest -q python/tests/test_fuzz.py

## Everything CI checks.
test: fmt lint cargo-test pytest

## The bundled scenes rendered (X, Y, Z, V′ EXRs with auto-exposed sRGB
## previews, and as the eye sees them: *-seen.png), the colorimetry of the
## demo lamps with plots, and the vision pipeline's stages for the night
## street at three light levels (*-stages.png, shown in docs/vision.md).
DEMO_SCENES := cornell-box material-showcase night-street prism

demo:
	$(CARGO) build --release -p scotopia
	@mkdir -p $(DEMO_OUT)
	@# The showcase keeps `path` in its file so Mitsuba reads it; the sun's
	@# caustics under the glass and gold balls need the bidirectional tracer.
	@# The Cornell box, the showcase and the night street get more samples
	@# than their files ask for, so that their pictures are not grainy as
	@# the eye sees them (the Cornell box's 64 are, in its shadows: 512 take
	@# about 30 s more). The night street's 176 take as long as 256 did
	@# before its diffuse bounces were aimed in part at the lamp-lit poles
	@# (README, "Fireflies in the demo"). About 3 minutes for the whole
	@# demo on 2 cores (183 s on 2026-12-04).
	@# The prism's light paths are guided out of its lamp's tube
	@# (docs/guiding.md): 128 guided spp take 75 s where its 256
	@# unguided took 112 s, and its spectrum is clean where it was
	@# confetti.
	@for s in $(DEMO_SCENES); do \
	  case $$s in cornell-box) i=; n=512; g=;; material-showcase) i=bdpt; n=192; g=;; night-street) i=; n=176; g=;; prism) i=; n=128; g=on;; *) i=; n=; g=;; esac; \
	  $(BIN) render scenes/$$s.xml $${i:+--integrator $$i} $${n:+--spp $$n} $${g:+--guiding $$g} -o $(DEMO_OUT)/$$s.exr --preview $(DEMO_OUT)/$$s.png; done
	@for lamp in A D65 F2 F11; do \
	  $(BIN) spectrum --illuminant $$lamp --plot $(DEMO_OUT)/illuminant-$$lamp.png > /dev/null; done
	@$(BIN) spectrum --file scenes/lamps/led-4000k.csv --plot $(DEMO_OUT)/led-4000k.png
	@$(BIN) spectrum --file scenes/lamps/low-pressure-sodium.csv --plot $(DEMO_OUT)/low-pressure-sodium.png
	@# The prism's spectrum as seen by someone looking at the screen (adapted
	@# to 30 cd/m²), not to the dark room's log-average.
	@for s in $(DEMO_SCENES); do \
	  case $$s in prism) a=30;; *) a=;; esac; \
	  $(BIN) display $(DEMO_OUT)/$$s.exr $${a:+--adaptation $$a} -o $(DEMO_OUT)/$$s-seen.png; done
	@# The night street at daylight, dusk and moonlight (every light scaled).
	@for level in day:800 dusk:4 moonlight:0.02; do \
	  $(BIN) display $(DEMO_OUT)/night-street.exr --scale $${level#*:} \
	    --compare $(DEMO_OUT)/night-street-$${level%%:*}-stages.png; done
	@echo "renders and plots in $(DEMO_OUT)/"

## Light that changes wavelength (fluorescence, dispersion): the black-light
## poster, white paper with and without brightener under D65 and A, the
## prism and the diamond; and light in fog: the foggy street at night and at
## dusk. Each as rendered (auto-exposed preview) and as seen (*-seen.png).
## The README's pictures are these.
GALLERY_OUT := out/gallery
FOG_SPP     := 256

gallery:
	$(CARGO) build --release -p scotopia
	@mkdir -p $(GALLERY_OUT)
	$(BIN) render scenes/black-light-poster.xml --spp 512 -o $(GALLERY_OUT)/black-light-poster.exr --preview $(GALLERY_OUT)/black-light-poster.png
	@for il in d65 a; do \
	  $(BIN) render scenes/paper.xml -D illuminant=$$il -o $(GALLERY_OUT)/paper-$$il.exr --preview $(GALLERY_OUT)/paper-$$il.png; done
	$(BIN) render scenes/prism.xml --spp 128 --guiding on -o $(GALLERY_OUT)/prism.exr --preview $(GALLERY_OUT)/prism.png
	$(BIN) render scenes/diamond.xml --spp 512 -o $(GALLERY_OUT)/diamond.exr --preview $(GALLERY_OUT)/diamond.png
	@for s in paper-d65 paper-a diamond; do \
	  $(BIN) display $(GALLERY_OUT)/$$s.exr -o $(GALLERY_OUT)/$$s-seen.png; done
	@# The poster and the prism's spectrum as seen by someone looking at the
	@# inks or the screen (adapted to 30 cd/m²), not to the dark room's
	@# log-average.
	@for s in black-light-poster prism; do \
	  $(BIN) display $(GALLERY_OUT)/$$s.exr --adaptation 30 -o $(GALLERY_OUT)/$$s-seen.png; done
	@# The night street in fog (volpath: at equal time its picture is
	@# cleaner than bdpt's, whose light-traced splats speckle the dark fog
	@# in colour), seen at night and at dusk (every light scaled by 4, as
	@# the night street's dusk).
	$(BIN) render scenes/foggy-street.xml --spp $(FOG_SPP) -o $(GALLERY_OUT)/foggy-street.exr --preview $(GALLERY_OUT)/foggy-street.png
	$(BIN) display $(GALLERY_OUT)/foggy-street.exr -o $(GALLERY_OUT)/foggy-street-night-seen.png
	$(BIN) display $(GALLERY_OUT)/foggy-street.exr --scale 4 -o $(GALLERY_OUT)/foggy-street-dusk-seen.png
	@echo "renders in $(GALLERY_OUT)/"

## The lighting-design example (docs/lighting.md): the street lit by three
## IES luminaires rendered (as rendered, as seen, and as a false-colour
## luminance map), its illuminance image in false colour, and the
## illuminance on EN 13201-3's grid between two poles with the EN 13201
## figures: average and minimum E and the overall uniformity U0 =
## Emin/Eavg (about 75 s on 2 cores).
LIGHT_OUT := out/lighting
STREET    := scenes/ies-street.xml

lighting:
	$(CARGO) build --release -p scotopia
	@mkdir -p $(LIGHT_OUT)
	$(BIN) render $(STREET) --spp 64 -o $(LIGHT_OUT)/ies-street.exr --preview $(LIGHT_OUT)/ies-street.png \
	  --radiance $(LIGHT_OUT)/ies-street.hdr
	@# Illuminance is mostly direct light here: 3 bounces are plenty. The
	@# eye's view, then a plan of the road between the first two poles.
	$(BIN) render $(STREET) --quantity illuminance --spp 16 -D max_depth=3 -o $(LIGHT_OUT)/ies-street-lux.exr
	$(BIN) render $(STREET) --quantity illuminance --spp 32 -D max_depth=3 \
	  -D origin=0.75,80,-15 -D target=0.75,0,-15 -D up=-1,0,0 -D fov=36 -o $(LIGHT_OUT)/ies-street-plan-lux.exr
	$(BIN) measure $(STREET) --points scenes/ies-street-grid.csv --spp 1024 -o $(LIGHT_OUT)/ies-street-grid-lux.csv
	@# The same grid at a face's height (1.5 m), facing +z: cylindrical and
	@# semi-cylindrical illuminance (EN 12464-1, EN 13201-2).
	@grep -v '^#' scenes/ies-street-grid.csv | awk -F, 'NR == 1 { print; next } { print $$1 ",1.5," $$3 ",0,0,1" }' \
	  > $(LIGHT_OUT)/ies-street-faces.csv
	$(BIN) measure $(STREET) --points $(LIGHT_OUT)/ies-street-faces.csv --receiver cylindrical --spp 1024 -o $(LIGHT_OUT)/ies-street-ez.csv
	$(BIN) measure $(STREET) --points $(LIGHT_OUT)/ies-street-faces.csv --receiver semicylindrical --spp 1024 -o $(LIGHT_OUT)/ies-street-esc.csv
	$(BIN) render $(STREET) --quantity melanopic-edi --spp 16 -D max_depth=3 -o $(LIGHT_OUT)/ies-street-medi.exr
	$(BIN) display $(LIGHT_OUT)/ies-street-medi.exr --false-colour melanopic-edi --range 0:25 -o $(LIGHT_OUT)/ies-street-medi.png
	$(BIN) display $(LIGHT_OUT)/ies-street.exr -o $(LIGHT_OUT)/ies-street-seen.png
	@for v in lux plan-lux; do \
	  $(BIN) display $(LIGHT_OUT)/ies-street-$$v.exr --false-colour illuminance --range 0:40 -o $(LIGHT_OUT)/ies-street-$$v.png; done
	$(BIN) display $(LIGHT_OUT)/ies-street.exr --false-colour luminance --range 0:2 -o $(LIGHT_OUT)/ies-street-cd.png
	@# The grid's figures, reading the columns by name (more may follow SP).
	@awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) col[$$i] = i; next } \
	  { e = $$col["E_lx"]; n++; sum += e; es += $$col["Es_lx"]; se += $$col["E_lx_se"]; mel += $$col["mEDI_lx"]; \
	    if (n == 1 || e < min) min = e; if (n == 1 || e > max) max = e } \
	  END { avg = sum / n; \
	    printf "\n%s, %d points (EN 13201-3 grid between two poles):\n", FILENAME, n; \
	    printf "  average E    Eavg = %6.2f lx   (mean SE of a point %.2f lx)\n", avg, se / n; \
	    printf "  minimum E    Emin = %6.2f lx\n", min; \
	    printf "  maximum E    Emax = %6.2f lx\n", max; \
	    printf "  uniformity   U0   = %6.2f     (Emin / Eavg)\n", min / avg; \
	    printf "  S/P               = %6.2f     (scotopic / photopic, grid means)\n", es / sum; \
	    printf "  melanopic    mEDI = %6.2f lx   (CIE S 026; %.2f of E)\n", mel / n, mel / sum }' \
	  $(LIGHT_OUT)/ies-street-grid-lux.csv
	@for r in ez esc; do awk -F, -v r=$$r 'NR == 1 { for (i = 1; i <= NF; i++) col[$$i] = i; next } \
	  { e = $$col["E_lx"]; n++; sum += e; if (n == 1 || e < min) min = e } \
	  END { printf "  %-12s %-4s = %6.2f lx   (average at 1.5 m%s; minimum %.2f lx)\n", \
	    (r == "ez" ? "cylindrical" : "semi-cyl."), (r == "ez" ? "Ez" : "Esc"), sum / n, \
	    (r == "ez" ? "" : ", facing +z"), min }' \
	  $(LIGHT_OUT)/ies-street-$$r.csv; done
	@# EN 13201-3's luminance method with the CIE R3 road: the standard's
	@# direct light, then the full transport; TI from each lamp at the eye.
	@echo; echo "ies-street.xml with an R3 road, EN 13201-3 luminance method (direct light, then full transport):"
	@$(BIN) road $(STREET) -D road=r3 --start=-3.5,0,0 --along 0,0,-1 --across 1,0,0 --spacing 30 --lanes 2 \
	  --spp 1024 --direct -o $(LIGHT_OUT)/ies-street-road.csv --grid $(LIGHT_OUT)/ies-street-road-grid.csv
	@$(BIN) road $(STREET) -D road=r3 --start=-3.5,0,0 --along 0,0,-1 --across 1,0,0 --spacing 30 --lanes 2 \
	  --spp 1024 | tail -n +3
	@# Glare at a driver's eye on the night street: a 180° fisheye, rated
	@# as evalglare rates it (sources above 2000 cd/m², its default).
	$(BIN) render scenes/night-street.xml -D sensor=fisheye -D fov=180 -D origin=0.8,1.5,6 \
	  -D target=0.8,1.5,-30 -D width=400 -D height=400 --spp 64 -o $(LIGHT_OUT)/night-street-eye.exr \
	  --radiance $(LIGHT_OUT)/night-street-eye.hdr
	@echo; echo "night-street.xml, 180° fisheye at a driver's eye (1.5 m), glare:"
	@$(BIN) glare $(LIGHT_OUT)/night-street-eye.exr --threshold 2000 -o $(LIGHT_OUT)/night-street-eye-sources.png
	@echo "renders, maps and the grid in $(LIGHT_OUT)/"

## criterion benchmarks, the bundled scenes' render rates and memory, and
## the Cornell box against Mitsuba 3 (bench/*.py print the README tables).
bench: python
	$(CARGO) bench -p scotopia-color -p scotopia-render -p scotopia-scene
	$(CARGO) build --release -p scotopia
	$(PY) bench/scenes.py --spp 16
	$(PY) bench/strategies.py
	$(PY) bench/bdpt.py
	$(PY) bench/vs_mitsuba.py
	$(PY) bench/vision.py
	$(PY) bench/distributed.py
	$(PY) bench/same_speed.py
	$(PY) bench/many_lights.py
	$(PY) bench/guiding.py

## Regenerates the Jakob–Hanika coefficient tables in data/rgb2spec.
tables:
	$(CARGO) run --release -p scotopia-color --bin scotopia-rgb2spec -- data/rgb2spec

clean:
	$(CARGO) clean
	rm -rf $(VENV) out
