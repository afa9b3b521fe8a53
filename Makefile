# signorini: the two commands that do everything are `make report` and `make test`.
CARGO ?= cargo
BIN := target/release/signorini

.PHONY: report report-fine report-finest rejudge league league-codes test test-report-shards golden build lint fmt experiment bench bench-fine stability figures reference verify-getfem verify-siconos docs mpi-check mpi-install cluster-plan

## Build, run the main studies (1D tables, gravity, round-off sensitivity, 2D and 3D convergence) and write reports/
## (tables, data, figures; README.md is the index). Each command writes its own study's data and
## pages; the last, `make figures`, builds from those data the pages that gather several studies
## (schemes.md, work-precision.md), the figures, the index and the one PNG.
## Each stage, the release build first, prints its wall time, and the total is printed at the end.
REPORT_STAGES := "$(CARGO) build --release" \
	"$(BIN) report --out reports" \
	"$(BIN) experiment --out reports" \
	"$(BIN) study scenes/bar2d.json --out reports" \
	"$(BIN) study scenes/bar3d.json --out reports" \
	"$(BIN) getfem --out reports" \
	"$(MAKE) --no-print-directory figures"
report:
	@started=$$(date +%s.%N); \
	for stage in $(REPORT_STAGES); do \
	  echo "$$stage"; begun=$$(date +%s.%N); \
	  sh -c "$$stage" || exit 1; \
	  echo "make report: \`$$stage\` took $$(awk "BEGIN { printf \"%.1f\", $$(date +%s.%N) - $$begun }") s wall"; \
	done; \
	echo "make report: total $$(awk "BEGIN { printf \"%.1f\", $$(date +%s.%N) - $$started }") s wall"

## The finer 2D/3D studies into reports/fine/: 2D levels 10–160 against a reference on
## 1280 elements, 3D levels 10–80 against 320, with their round-off ensembles and figures. The
## references are kept in the user's cache ($SIGNORINI_CACHE, else ~/.cache/signorini/references;
## computing them takes most of the time: see docs/src/convergence-2d-3d.md).
report-fine: build
	$(BIN) study scenes/bar2d-fine.json --out reports/fine
	$(BIN) study scenes/bar3d-fine.json --out reports/fine
	$(BIN) figures --out reports/fine

## The finest 3D study into reports/finest/: levels 10–160 against a reference on 640 elements
## along the axis (8.1 M unknowns, 2 560 steps), with the round-off ensembles and figures. The
## reference takes most of the time and memory (reports/finest/elastic-3d.md gives its run time;
## docs/src/make-targets.md); it is kept in the user's cache.
report-finest: build
	$(BIN) study scenes/bar3d-finest.json --out reports/finest
	$(BIN) figures --out reports/finest

## The committed 2D/3D studies (reports/, reports/fine/, reports/finest/) judged again from their
## elastic-<d>d.json without running anything: their findings and reports rewritten by the
## current rule (docs/src/convergence-2d-3d.md, "The note's findings"), then the indexes.
rejudge: build
	$(BIN) rejudge scenes/bar2d.json --out reports
	$(BIN) rejudge scenes/bar3d.json --out reports
	$(BIN) rejudge scenes/bar2d-fine.json --out reports/fine
	$(BIN) rejudge scenes/bar3d-fine.json --out reports/fine
	$(BIN) rejudge scenes/bar3d-finest.json --out reports/finest
	$(BIN) figures --out reports/fine
	$(BIN) figures --out reports/finest
	$(BIN) figures --out reports

## The fine-mesh references of the 2D/3D studies, into the user's cache ($SIGNORINI_CACHE, else
## ~/.cache/signorini/references), which study, verify and the league share: the cache is kept
## when its parameters match the scenes', recomputed otherwise (make report does the same).
reference: build
	$(BIN) reference scenes/bar2d.json scenes/bar3d.json

## Run the test suite with cargo-nextest (installed first if missing), and a system font for the
## figure test to lay text out with (Debian's fonts-dejavu-core, installed if no font is).
test:
	@$(CARGO) nextest --version >/dev/null 2>&1 || $(CARGO) install cargo-nextest --locked
	@ls /usr/share/fonts/truetype/*/*.ttf >/dev/null 2>&1 || (apt-get update -qq && apt-get install -y -qq fonts-dejavu-core)
	$(CARGO) nextest run

## The long tests of `report` and `experiment` sharded, which `make test` skips: in process, the
## tables' studies and the experiment's, three shards merged against the unsharded run; end to
## end, the whole `signorini report` and `experiment` run unsharded and as three shards, and
## their merges compared with them (the report twice: most of the time).
test-report-shards:
	@$(CARGO) nextest --version >/dev/null 2>&1 || $(CARGO) install cargo-nextest --locked
	$(CARGO) nextest run --run-ignored only -E 'test(/^report_shards::/) | test(/^shards::the_merge_of_three_(report|experiment)_shards/)'

## The ParaView reader fuzzed for a fixed time (FUZZ_SECONDS, default 120) from a seed taken
## from the clock and printed (replay one with SIGNORINI_FUZZ_SEED=<seed>): mutated snapshots of
## every real writer's files, each read or refused, never a panic (tests/unit/paraview_fuzz.rs).
.PHONY: fuzz-paraview
FUZZ_SECONDS ?= 120
fuzz-paraview:
	@$(CARGO) nextest --version >/dev/null 2>&1 || $(CARGO) install cargo-nextest --locked
	SIGNORINI_FUZZ_SECONDS=$(FUZZ_SECONDS) $(CARGO) nextest run --run-ignored only --no-capture -E 'test(fuzz_the_paraview_reader_for_a_fixed_time)'

## Regenerate the golden rates and the table snapshot (the only way they change).
golden: build
	$(BIN) golden --out .
	INSTA_UPDATE=always $(CARGO) nextest run --test convergence -E 'test(/^gate::/)'

## The experiment behind the default horizon and levels (also part of `make report`).
experiment: build
	$(BIN) experiment --out reports

## The stability suite: every scheme × mass of the tables, the paper's and the rivals', on the hard
## cases (the NX = 5000 case takes most of its time), then the figures and schemes.md with the
## suite's section.
stability: build
	$(BIN) stability --out reports
	$(BIN) figures --out reports

## The render step from the data in reports/: the pages that gather several studies (schemes.md,
## work-precision.md), the figures and the index, and one figure rendered to PNG for a person to
## look at (rsvg-convert, from Debian's librsvg2-bin, installed if missing).
figures: build
	$(BIN) figures --out reports
	@command -v rsvg-convert >/dev/null || (apt-get update -qq && apt-get install -y -qq librsvg2-bin)
	rsvg-convert -o reports/figures/contact-crank-nicolson.png reports/figures/contact-crank-nicolson.svg

## GetFEM's demo runs (tests/data/getfem) solved again with its conventions, compared step by
## step with the demo's arrays and norms: reports/getfem.md; the runs as external-run files
## (target/getfem-runs/, derived in under a second) verified like any other code's:
## reports/getfem-verify/.
verify-getfem: build
	$(BIN) getfem --out reports --export target/getfem-runs
	$(BIN) verify scenes/bar1d-dirichlet.json target/getfem-runs/*.csv --out reports/getfem-verify

## Siconos as an external witness of the harness's Moreau–Jean scheme: scripts/siconos_bar.py
## (Debian's python3-siconos, installed if /usr/bin/python3 cannot import it) integrates the
## harness's discrete 1D bar (standard mass, the scene's data and time grid) with Siconos's
## MoreauJeanOSI (θ = ½, NewtonImpactNSL e = 0, LCP) at every level below, written as external
## runs (target/siconos-runs/), verified like any other code's into reports/league/siconos-1d/,
## and the league table rewritten with it (reports/league.md).
SICONOS_RUNS := target/siconos-runs
SICONOS_LEVELS := 10 20 40 80 160
verify-siconos: build
	@/usr/bin/python3 -c 'import siconos' 2>/dev/null || (apt-get update -qq && apt-get install -y -qq python3-siconos)
	rm -rf $(SICONOS_RUNS)
	/usr/bin/python3 scripts/siconos_bar.py --nx $(SICONOS_LEVELS) --out $(SICONOS_RUNS)
	$(BIN) verify scenes/bar1d-dirichlet.json $(SICONOS_RUNS)/*.json --out reports/league/siconos-1d
	$(BIN) league reports/league --out reports

## The league table, reports/league.md and league.json: every external run set verified side by side
## into reports/league/<entry>/ (GetFEM's 1D demo runs; GetFEM's own 2D and 3D runs, written in the
## box form by `signorini getfem-box`; GetFEM's and DOLFINx's own solves of the 2D bar at every
## level of LEAGUE_2D_LEVELS, every step written by each code's own writer (`league-codes`); the
## harness's own 2D and 3D runs, exported at every step as ParaView collections), then any other
## entry already there (your code's: docs/src/external-runs.md). The 2D/3D entries use the
## references in the user's cache (computed there by the first command that needs one).
LEAGUE_RUNS := target/league
LEAGUE_2D_LEVELS := 10 20 40 80
LEAGUE_3D_LEVELS := 10 20 40
LEAGUE_SCHEMES := crank-nicolson backward-euler
LEAGUE_MASSES := standard redistributed

## Two other codes solve the 2D bar as the harness does and write it their own way, verified as
## they wrote it: GetFEM 5.4.2 (scripts/getfem_bar2d.py: its model bricks, Newmark or θ = 1, its
## nodal contact brick; `MeshFem.export_to_vtu` in base64, Float32) and DOLFINx 0.5.2
## (scripts/dolfinx_bar2d.py: its Q1 matrices, the harness's one-step schemes, an exact nodal LCP;
## `dolfinx.io.VTKFile`, .pvd -> .pvtu -> .vtu); then DOLFINx on its default triangle mesh of the
## bar and GetFEM on its regular simplices of it (both P1, `--cell triangle`), each verified on
## its own mesh. Debian's python3-getfem and python3-dolfinx are installed if /usr/bin/python3
## cannot import them.
league-codes: build
	@/usr/bin/python3 -c 'import getfem' 2>/dev/null || (apt-get update -qq && apt-get install -y -qq python3-getfem)
	@/usr/bin/python3 -c 'import dolfinx' 2>/dev/null || (apt-get update -qq && apt-get install -y -qq python3-dolfinx)
	rm -rf $(LEAGUE_RUNS)/getfem-vtu $(LEAGUE_RUNS)/dolfinx $(LEAGUE_RUNS)/dolfinx-triangles \
	  $(LEAGUE_RUNS)/getfem-triangles
	for scheme in $(LEAGUE_SCHEMES); do for mass in $(LEAGUE_MASSES); do \
	  /usr/bin/python3 scripts/getfem_bar2d.py --level $(LEAGUE_2D_LEVELS) --scheme $$scheme --mass $$mass \
	    --binary --out $(LEAGUE_RUNS)/getfem-vtu 2>/dev/null >/dev/null || exit 1; \
	  $(BIN) verify scenes/bar2d.json $(LEAGUE_RUNS)/getfem-vtu/getfem-$$scheme-$$mass-nx*-binary.pvd \
	    --code getfem --code-version 5.4.2 --label "GetFEM $$scheme, $$mass (its VTU exporter)" \
	    --scheme $$scheme --mass $$mass --contact "nodal contact brick, Alart-Curnier (Newton)" \
	    --velocity velocity --multiplier multiplier \
	    --out reports/league/getfem-vtu-2d-$$scheme-$$mass >/dev/null || exit 1; \
	  /usr/bin/python3 scripts/dolfinx_bar2d.py --level $(LEAGUE_2D_LEVELS) --scheme $$scheme --mass $$mass \
	    --out $(LEAGUE_RUNS)/dolfinx >/dev/null || exit 1; \
	  $(BIN) verify scenes/bar2d.json $(LEAGUE_RUNS)/dolfinx/dolfinx-bar2d-$$scheme-$$mass-level*.pvd \
	    --code dolfinx --code-version 0.5.2 --label "DOLFINx $$scheme, $$mass (VTKFile)" \
	    --scheme $$scheme --mass $$mass --contact "exact nodal complementarity (LCP)" \
	    --velocity velocity --multiplier contact_multiplier \
	    --out reports/league/dolfinx-2d-$$scheme-$$mass >/dev/null || exit 1; \
	  /usr/bin/python3 scripts/dolfinx_bar2d.py --level $(LEAGUE_2D_LEVELS) --scheme $$scheme --mass $$mass \
	    --cell triangle --out $(LEAGUE_RUNS)/dolfinx-triangles >/dev/null || exit 1; \
	  $(BIN) verify scenes/bar2d.json \
	    $(LEAGUE_RUNS)/dolfinx-triangles/dolfinx-bar2d-triangle-$$scheme-$$mass-level*.pvd \
	    --code dolfinx --code-version 0.5.2 --label "DOLFINx $$scheme, $$mass, its triangles (VTKFile)" \
	    --scheme $$scheme --mass $$mass --contact "exact nodal complementarity (LCP)" \
	    --velocity velocity --multiplier contact_multiplier \
	    --out reports/league/dolfinx-triangles-2d-$$scheme-$$mass >/dev/null || exit 1; \
	  /usr/bin/python3 scripts/getfem_bar2d.py --level $(LEAGUE_2D_LEVELS) --scheme $$scheme --mass $$mass \
	    --cell triangle --binary --out $(LEAGUE_RUNS)/getfem-triangles 2>/dev/null >/dev/null || exit 1; \
	  $(BIN) verify scenes/bar2d.json \
	    $(LEAGUE_RUNS)/getfem-triangles/getfem-triangle-$$scheme-$$mass-nx*-binary.pvd \
	    --code getfem --code-version 5.4.2 --label "GetFEM $$scheme, $$mass, its triangles (its VTU exporter)" \
	    --scheme $$scheme --mass $$mass --contact "nodal contact brick, Alart-Curnier (Newton)" \
	    --velocity velocity --multiplier multiplier \
	    --out reports/league/getfem-triangles-2d-$$scheme-$$mass >/dev/null || exit 1; \
	done; done

league: build league-codes
	rm -rf $(LEAGUE_RUNS)/getfem-1d* $(LEAGUE_RUNS)/getfem-2d $(LEAGUE_RUNS)/getfem-3d $(LEAGUE_RUNS)/signorini-*
	$(BIN) getfem --out $(LEAGUE_RUNS)/getfem-1d-report --export $(LEAGUE_RUNS)/getfem-1d
	$(BIN) verify scenes/bar1d-dirichlet.json $(LEAGUE_RUNS)/getfem-1d/*.csv --out reports/league/getfem-1d
	$(BIN) getfem-box tests/data/getfem2d/*.json.gz --out $(LEAGUE_RUNS)/getfem-2d
	$(BIN) verify scenes/bar2d.json $(LEAGUE_RUNS)/getfem-2d/*.json --out reports/league/getfem-2d
	$(BIN) getfem-box tests/data/getfem3d/*.json.gz --out $(LEAGUE_RUNS)/getfem-3d
	$(BIN) verify scenes/bar3d.json $(LEAGUE_RUNS)/getfem-3d/*.json --out reports/league/getfem-3d
	for d in 2 3; do \
	  levels="$(LEAGUE_2D_LEVELS)"; [ $$d = 3 ] && levels="$(LEAGUE_3D_LEVELS)"; \
	  for scheme in crank-nicolson backward-euler; do for mass in standard redistributed; do \
	    for level in $$levels; do \
	      $(BIN) run scenes/bar$${d}d.json --scheme $$scheme --mass $$mass --nx $$level \
	        --fields-every-step --out $(LEAGUE_RUNS)/signorini-$${d}d/$$scheme-$$mass-$$level >/dev/null || exit 1; \
	    done; \
	    $(BIN) verify scenes/bar$${d}d.json $(LEAGUE_RUNS)/signorini-$${d}d/$$scheme-$$mass-*/fields.pvd \
	      --code signorini --code-version $$($(BIN) --version | cut -d' ' -f2) \
	      --label "signorini $$scheme, $$mass" --scheme $$scheme --mass $$mass \
	      --contact "multiplier (exact complementarity)" --velocity velocity --multiplier contact_multiplier \
	      --out reports/league/signorini-$${d}d-$$scheme-$$mass >/dev/null || exit 1; \
	  done; done; \
	done
	$(BIN) league reports/league --out reports
	$(BIN) figures --out reports

## The distributed step solve under MPI (issue 36): installs Open MPI (Debian's openmpi-bin and
## libopenmpi-dev, and libclang-dev for the bindings' generator) when they are missing, builds
## the `mpi` feature and runs tests/mpi.rs, which runs the solve under mpirun on 1 and 2 ranks
## against the one-process solve. `.ci/run` runs it after `make test`.
mpi-check: mpi-install
	@$(CARGO) nextest --version >/dev/null 2>&1 || $(CARGO) install cargo-nextest --locked
	$(CARGO) clippy --features mpi --lib --test mpi -- -D warnings
	$(CARGO) nextest run --features mpi --test mpi

mpi-install:
	@dpkg -s openmpi-bin libopenmpi-dev libclang-dev >/dev/null 2>&1 || (apt-get update -qq && apt-get install -y -qq openmpi-bin libopenmpi-dev libclang-dev)

## The plan of the 3D bar's 1 280-element reference across a cluster (issue 36; about 5 min):
## its reference on 80 and 160 elements computed and measured (`reference --measure`) in one
## process of every thread and on 3 and 4 MPI ranks of one thread (memory), and three times
## each in one process of one thread and on 2 ranks of one thread (time and memory); the cost
## model fitted to them, checked against the finest study's one-process reference
## (reports/finest/elastic-3d.json) and its answer for 1 to 32 nodes written to
## reports/cluster/ (cluster-plan.md, cluster-plan.json, and the measurements in measured/).
CLUSTER := reports/cluster
MPI_BIN := target/mpi/release/signorini
MPIRUN := OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 RAYON_NUM_THREADS=1 mpirun --oversubscribe
cluster-plan: mpi-install
	CARGO_TARGET_DIR=target/mpi $(CARGO) build --release --features mpi
	rm -rf $(CLUSTER)/measured $(CLUSTER)/work && mkdir -p $(CLUSTER)/measured $(CLUSTER)/work
	for level in 80 160; do \
	  sed "s/\"reference_level\": [0-9]*/\"reference_level\": $$level/" scenes/bar3d.json > $(CLUSTER)/work/bar3d-$$level.json && \
	  $(MPI_BIN) reference $(CLUSTER)/work/bar3d-$$level.json --cache $(CLUSTER)/work/n1-$$level --measure $(CLUSTER)/measured/$$level-ranks1-threads$$(nproc).json && \
	  $(MPIRUN) -n 3 $(MPI_BIN) reference $(CLUSTER)/work/bar3d-$$level.json --cache $(CLUSTER)/work/n3-$$level --measure $(CLUSTER)/measured/$$level-ranks3-threads1.json && \
	  $(MPIRUN) -n 4 $(MPI_BIN) reference $(CLUSTER)/work/bar3d-$$level.json --cache $(CLUSTER)/work/n4-$$level --measure $(CLUSTER)/measured/$$level-ranks4-threads1.json && \
	  for run in 1 2 3; do \
	    RAYON_NUM_THREADS=1 $(MPI_BIN) reference $(CLUSTER)/work/bar3d-$$level.json --cache $(CLUSTER)/work/n1t1-$$level-$$run --measure $(CLUSTER)/measured/$$level-ranks1-threads1-run$$run.json && \
	    $(MPIRUN) -n 2 $(MPI_BIN) reference $(CLUSTER)/work/bar3d-$$level.json --cache $(CLUSTER)/work/n2-$$level-$$run --measure $(CLUSTER)/measured/$$level-ranks2-threads1-run$$run.json || exit 1; \
	  done || exit 1; \
	done
	$(MPI_BIN) cluster-plan scenes/bar3d.json --level 1280 --nodes 1,2,4,8,16,32 --measured $(CLUSTER)/measured/*.json --measured-cores $$(nproc) --check reports/finest/elastic-3d.json --out $(CLUSTER)
	rm -rf $(CLUSTER)/work

## Speed side by side (scripts/bench.py): the baseline, the merge-base of HEAD with origin/main
## (main without an origin) or BASELINE=<commit>, is built beside the working tree
## (scripts/bench_baseline.sh, into target/bench-baseline/) and both binaries are run in
## alternation in one go: the step kernels of every scheme × mass at NX = 640, the Tables 1–2
## study, the 3D runs at levels 80 and 160, each a ratio of CPU
## times with its range; and what the per-step checks cost (the same binary with them off).
## reports/bench.md and bench.json get the figures; exits non-zero on a regression (a ratio
## whose whole range lies above 1.10) or a check above its bound. BENCH_REPEATS pairs per figure.
BASELINE ?=
BENCH_REPEATS ?= 5
bench: build
	@set -e; found=$$(scripts/bench_baseline.sh $(BASELINE)); set -- $$found; \
	python3 scripts/bench.py --current $(BIN) --baseline $$1 --baseline-commit $$2 --repeats $(BENCH_REPEATS)

## `make bench` with a round-off sensitivity study (3 pairs) and the 3D level-320 run (one pair).
bench-fine: build
	@set -e; found=$$(scripts/bench_baseline.sh $(BASELINE)); set -- $$found; \
	python3 scripts/bench.py --current $(BIN) --baseline $$1 --baseline-commit $$2 --repeats $(BENCH_REPEATS) --fine

build:
	$(CARGO) build --release

lint:
	$(CARGO) fmt --all -- --check
	$(CARGO) clippy --all-targets -- -D warnings

fmt:
	$(CARGO) fmt --all

## The book (docs/src/, mdBook) into docs/book/; mdbook is installed first if it is missing.
docs:
	@command -v mdbook >/dev/null || $(CARGO) install mdbook --locked
	mdbook build docs
