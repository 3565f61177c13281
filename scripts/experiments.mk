# Experiments around Table 1 of Nah, Heo, Park, Han, "A Split Node Cache
# Scheme for Fast Ray Tracing" (RT'08): the table as the paper lays it out,
# and the studies that explain it. README "Experiments" lists the targets and
# their outputs.
#
#   make -f scripts/experiments.mk table1            # or: make -f scripts/table1.mk
#   make -f scripts/experiments.mk -j2 all
#   make -f scripts/experiments.mk table1 SCENES=robot WIDTH=64 HEIGHT=48
#   make -f scripts/experiments.mk -j64 RUN="srun --ntasks=1 --cpus-per-task=2" frames
#
# Rebuilds are decided by content, not by file times: a trace's file name is a
# hash of everything that changes its records (the tracer binary, every file
# of the scene's folder, the tracer options), a simulation's name a hash of
# its trace's name, the cachesim binary and its options. A trace exists or is
# rendered; it is never stale, and never rendered twice. Each target's list of
# inputs (its manifest) is rewritten only when its content changes, so a
# table is remade exactly when its set of inputs or one of them changes.
#
# Every recipe that renders or simulates runs through $(RUN) (empty: here);
# recipes share nothing but the files under $(OUT), so a cluster can run them.

MK_FILE := $(lastword $(MAKEFILE_LIST))
MK_DIR := $(patsubst %/,%,$(dir $(MK_FILE)))

BUILD ?= build
SHARED ?= ../shared
OUT ?= out
RUN ?=
PYTHON ?= /usr/bin/python3

TRACER := $(BUILD)/bin/tracer
CACHESIM := $(BUILD)/bin/cachesim
TRACETOOL := $(BUILD)/bin/tracetool
TRACES := $(OUT)/traces
REPORTS := $(MK_DIR)/reports

# --- The paper's setting (Table 1) and the parameters it leaves open --------
WIDTH ?= 800
HEIGHT ?= 600
DEPTH ?= 10
FRAME ?= 0
SCENES ?= robot kitchen forest
SIZES ?= 4k 8k 16k
BLOCK ?= 8
# kd-tree build: 'default' depth limit is the tracer's 8 + 1.3 log2 N.
TREE_DEPTH ?= default
TRAVERSAL_COST ?= 1
INTERSECTION_COST ?= 1.5
EMPTY_BONUS ?= 0.2

# --- Studies ------------------------------------------------------------------
BASELINE_LAYOUTS ?= dfl bfl veb
ASSOCS ?= 1 2 4 8 full
SENS_SCENES ?= robot
SENS_SIZE ?= 16k
SENS_WIDTH ?= 400
SENS_HEIGHT ?= 300
SENS_K ?= 2 4 6 8 10
SENS_TREE_DEPTHS ?= 12 16 20 24 29
SENS_RESOLUTIONS ?= 100x75 200x150 400x300 800x600
# Calibration grid: settings DEPTHLIMIT:TRAVERSAL:INTERSECTION:EMPTYBONUS.
CAL_SCENES ?= robot kitchen
CAL_WIDTH ?= 200
CAL_HEIGHT ?= 150
CAL_TREE_DEPTHS ?= 16 20 24 default
CAL_COSTS ?= 1:1.5 1:4 1:10
CAL_EMPTY_BONUSES ?= 0.2 0.8
CAL_BEST ?= 3
CAL_FINAL_WIDTH ?= $(WIDTH)
CAL_FINAL_HEIGHT ?= $(HEIGHT)
# Animation: every FRAME_STEP-th frame of FRAME_FIRST..FRAME_LAST.
FRAME_SCENES ?= robot kitchen
FRAME_SIZES ?= 16k
FRAME_FIRST ?= 0
FRAME_LAST ?= 799
FRAME_STEP ?= 40
FRAME_WIDTH ?= $(WIDTH)
FRAME_HEIGHT ?= $(HEIGHT)
# Sampling: each method at each rate 1/R and seed, against the full run.
SAMPLING_SCENES ?= robot kitchen
SAMPLING_SIZES ?= $(SIZES)
SAMPLING_METHODS ?= rows windows sets
SAMPLING_RATES ?= 2 4 8 16 32 64
SAMPLING_SEEDS ?= 1 2
SAMPLING_WINDOW_RECORDS ?= 1048576

scene_robot := $(SHARED)/scenes/bart/robots/Robot.aff
scene_kitchen := $(SHARED)/scenes/bart/kitchen/kitchen.aff
# The paper's Fairy Forest is not available; the built-in forest stands in.
scene_forest := forest

# --- Helpers ------------------------------------------------------------------
empty :=
space := $(empty) $(empty)
comma := ,
join_commas = $(subst $(space),$(comma),$(strip $1))

# Hashes are 16 hex digits; anything else (a failed shell) stops make.
hex_split = $(subst 0,0 ,$(subst 1,1 ,$(subst 2,2 ,$(subst 3,3 ,$(subst 4,4 ,$(subst 5,5 ,$(subst 6,6 ,$(subst \
  7,7 ,$(subst 8,8 ,$(subst 9,9 ,$(subst a,a ,$(subst b,b ,$(subst c,c ,$(subst d,d ,$(subst e,e ,$(subst f,f ,$1))))))))))))))))
checked_hash = $(if $(and $(filter 16,$(words $(call hex_split,$1))),$(filter 1,$(words $1))),$1,$(error \
  could not hash $2 (got '$1')))
hash_text = $(call checked_hash,$(shell printf '%s' '$1' | sha256sum | cut -c1-16),the options '$1')
file_hash = $(call checked_hash,$(shell sha256sum < '$1' | cut -c1-16),$1)

# Hashes are computed on first use only, so `make clean` needs no build.
need_program = $(if $(wildcard $1),,$(error $1 not found: build first (scripts/setup.sh)))
tracer_hash = $(or $(tracer_hash_value),$(call need_program,$(TRACER))$(eval tracer_hash_value := $(call file_hash,$(TRACER)))$(tracer_hash_value))
cachesim_hash = $(or $(cachesim_hash_value),$(call need_program,$(CACHESIM))$(eval cachesim_hash_value := $(call file_hash,$(CACHESIM)))$(cachesim_hash_value))

# A file scene is every file of its folder (an AFF file includes others); a
# built-in scene is its name, its geometry being part of the tracer binary.
scene_arg = $(or $(scene_$1),$(error unknown scene '$1' (expected robot, kitchen, forest)))
scene_hash = $(or $(scene_hash_$1),$(eval scene_hash_$1 := $(call compute_scene_hash,$1))$(scene_hash_$1))
compute_scene_hash = $(if $(findstring /,$(call scene_arg,$1)),$(if $(wildcard $(scene_$1)),$(call checked_hash,$(shell \
  cd '$(dir $(scene_$1))' && find . -type f | LC_ALL=C sort | xargs -r sha256sum | sha256sum | cut -c1-16),scene $1),$(error scene $1: $(scene_$1) not found (SHARED=$(SHARED)))),builtin-$(scene_$1))

# Bytes of a size such as 16k or 1m, and half of it (the paper's split).
size_bytes = $(or $(shell echo $$(( $(subst k,*1024,$(subst m,*1048576,$1)) ))),$(error bad size '$1' (expected e.g. 4k)))
half_size = $(shell echo $$(( $(call size_bytes,$1) / 2 )))

# kd-tree build options: DEPTHLIMIT TRAVERSAL INTERSECTION EMPTYBONUS.
kd_options = --traversal-cost $2 --intersection-cost $3 --empty-bonus $4$(if $(filter default,$1),, --tree-depth $1)
kd_default := $(call kd_options,$(TREE_DEPTH),$(TRAVERSAL_COST),$(INTERSECTION_COST),$(EMPTY_BONUS))
# Render options: WIDTH HEIGHT FRAME KD-OPTIONS.
render_options = --width $1 --height $2 --max-depth $(DEPTH) --frame $3 $4
render_default := $(call render_options,$(WIDTH),$(HEIGHT),$(FRAME),$(kd_default))
hybrid_for = --layout hybrid --high-size $(call half_size,$1)

# $(call trace,SCENE,TRACER-OPTIONS): the trace of that scene rendered with
# those options; its rule is defined on first use.
trace = $(call define_trace,$(TRACES)/$1-$(call hash_text,$(tracer_hash) $(call scene_hash,$1) $2).din.zst,$1,$2)
define_trace = $(if $(defined_$1),,$(eval $(call trace_rule,$1,$2,$3,$(words $(all_traces) x)))$(eval defined_$1 := 1)$(eval all_traces += $1))$1
define trace_rule
$1: | $(TRACES)/.dir
	@echo "render [$$(words $$(wildcard $$(to_render)) x) of $$(words $$(to_render))] $2 $3" >&2
	@$(RUN) $(TRACER) render $(call scene_arg,$2) -q $3 -o $$@
endef

# $(call sim,TARGET,TRACE,CACHESIM-OPTIONS): cachesim's CSV for that trace.
sim = $(call define_sim,$(OUT)/$1/runs/$(call hash_text,$(cachesim_hash) $2 $3).csv,$2,$3)
define_sim = $(if $(defined_$1),,$(eval $(call sim_rule,$1,$2,$3))$(eval defined_$1 := 1))$1
define sim_rule
$1: $2 | $(dir $1).dir
	@echo "simulate $(notdir $2) $3" >&2
	@$(RUN) $(CACHESIM) run $2 $(subst --per-level,--per-level $$@.levels.tmp$$$$$$$$,$3) --format csv \
	  > $$@.tmp$$$$$$$$ $(if $(findstring --per-level,$3),&& mv $$@.levels.tmp$$$$$$$$ $$@.levels.csv) \
	  && mv $$@.tmp$$$$$$$$ $$@ || { rm -f $$@.tmp$$$$$$$$ $$@.levels.tmp$$$$$$$$; exit 1; }
endef
sim_files = $(filter %.csv,$(subst =, ,$(subst ;, ,$1)))

# A target's manifest: one line KIND;key=value;... per word of $($1_lines),
# the file rewritten only when its content changed.
define manifest_rule
$(OUT)/$1/manifest.txt: FORCE | $(OUT)/$1/.dir
	@printf '%s\n' $$(foreach line,$$($1_lines),'$$(line)') > $$@.tmp
	@if cmp -s $$@.tmp $$@; then rm -f $$@.tmp; else mv -f $$@.tmp $$@; fi
endef

# A study: its manifest, its runs, and one Python script (reports/NAME.py)
# that writes $1.csv, $1.md and the figures $($1_figures) from them.
define study_rule
$(eval $(call manifest_rule,$1))
$1_outputs := $(addprefix $(OUT)/$1/,$1.csv $1.md $($1_figures))
$$($1_outputs) &: $(OUT)/$1/manifest.txt $(call sim_files,$($1_lines)) $(REPORTS)/$(subst -,_,$1).py \
    $(REPORTS)/common.py $(MK_DIR)/paper-table1.csv
	@echo "report $1" >&2
	@$(PYTHON) $(REPORTS)/$(subst -,_,$1).py $(OUT)/$1/manifest.txt $(OUT)/$1 --paper $(MK_DIR)/paper-table1.csv
$1: $$($1_outputs)
	@cat $(OUT)/$1/$1.md
endef

# Parameters every report states.
common_params = param;width=$(WIDTH) param;height=$(HEIGHT) param;frame=$(FRAME) \
  param;max_ray_depth=$(DEPTH) param;block=$(BLOCK) param;tree_depth=$(TREE_DEPTH) \
  param;traversal_cost=$(TRAVERSAL_COST) param;intersection_cost=$(INTERSECTION_COST) \
  param;empty_bonus=$(EMPTY_BONUS) param;tracetool=$(TRACETOOL)

# Only the targets asked for are worked out (hashes, rules): `make clean`
# needs no build, `make table1 SCENES=forest` no ../shared.
.DEFAULT_GOAL := $(or $(.DEFAULT_GOAL),all)
goals := $(or $(MAKECMDGOALS),$(.DEFAULT_GOAL))
wanted = $(filter $1 all,$(goals))

.PHONY: all table1 baselines assoc levels sensitivity calibration calibration-grid frames sampling clean FORCE
.DELETE_ON_ERROR:

# Every study; `all` makes them (a new study adds its target here and its section below).
ALL_TARGETS := table1 baselines assoc levels sensitivity calibration frames sampling
all: $(ALL_TARGETS)

%/.dir:
	@mkdir -p $(@D) && touch $@

# --- table1: Robot, Kitchen, forest; 4/8/16 KB; single and split -----------
# "without" is the single cache over the same hybrid-layout trace as "with".
table1_figures := table1.png
ifneq ($(call wanted,table1),)
table1_lines := $(common_params) param;layout_without=hybrid \
  $(foreach s,$(SCENES),$(foreach z,$(SIZES),row;scene=$s;size=$z;file=$(call sim,table1,$(call \
  trace,$s,$(render_default) $(call hybrid_for,$z)),--size $z --block $(BLOCK) --assoc 1 --scheme \
  single$(comma)split --split-level auto)))
$(eval $(call study_rule,table1))
endif

# --- baselines: the single cache over each layout, against the split --------
baselines_figures := baselines.png
ifneq ($(call wanted,baselines),)
baselines_lines := $(common_params) \
  $(foreach s,$(SCENES),$(foreach l,$(BASELINE_LAYOUTS),row;scene=$s;layout=$l;file=$(call \
  sim,baselines,$(call trace,$s,$(render_default) --layout $l),--size $(call join_commas,$(SIZES)) \
  --block $(BLOCK) --assoc 1 --scheme single)) \
  $(foreach z,$(SIZES),row;scene=$s;layout=hybrid;file=$(call sim,baselines,$(call \
  trace,$s,$(render_default) $(call hybrid_for,$z)),--size $z --block $(BLOCK) --assoc 1 --scheme \
  single$(comma)split --split-level auto)))
$(eval $(call study_rule,baselines))
endif

# --- assoc: split minus single against associativity and size --------------
assoc_figures := assoc.png
ifneq ($(call wanted,assoc),)
assoc_lines := $(common_params) \
  $(foreach s,$(SCENES),$(foreach z,$(SIZES),row;scene=$s;size=$z;file=$(call sim,assoc,$(call \
  trace,$s,$(render_default) $(call hybrid_for,$z)),--size $z --block $(BLOCK) --assoc \
  $(call join_commas,$(ASSOCS)) --scheme single$(comma)split --split-level auto)))
$(eval $(call study_rule,assoc))
endif

# --- levels: miss ratio per node level, single against split ---------------
levels_figures := $(foreach s,$(SCENES),levels-$s.png)
ifneq ($(call wanted,levels),)
levels_lines := $(common_params) \
  $(foreach s,$(SCENES),$(foreach z,$(SIZES),row;scene=$s;size=$z;file=$(call sim,levels,$(call \
  trace,$s,$(render_default) $(call hybrid_for,$z)),--size $z --block $(BLOCK) --assoc 1 --scheme \
  single$(comma)split --split-level auto --per-level)))
$(eval $(call study_rule,levels))
endif

# --- sensitivity: the gain against K, the depth limit, the resolution ------
# One parameter at a time around the setting above, at SENS_WIDTH x SENS_HEIGHT.
sensitivity_figures := sensitivity.png
ifneq ($(call wanted,sensitivity),)
sens_sim = $(call sim,sensitivity,$(call trace,$1,$2),--size $(SENS_SIZE) --block $(BLOCK) --assoc 1 \
  --scheme single$(comma)split --split-level $3)
sens_render = $(call render_options,$(SENS_WIDTH),$(SENS_HEIGHT),$(FRAME),$1)
sens_depth_kd = $(call kd_options,$1,$(TRAVERSAL_COST),$(INTERSECTION_COST),$(EMPTY_BONUS))
sens_res_render = $(call render_options,$(word 1,$(subst x, ,$1)),$(word 2,$(subst x, ,$1)),$(FRAME),$(kd_default))
sensitivity_lines := $(common_params) param;sens_size=$(SENS_SIZE) param;sens_width=$(SENS_WIDTH) \
  param;sens_height=$(SENS_HEIGHT) \
  $(foreach s,$(SENS_SCENES), \
    $(foreach k,$(SENS_K),row;scene=$s;study=K;value=$k;file=$(call sens_sim,$s,$(call \
      sens_render,$(kd_default)) --layout hybrid --split-level $k,$k)) \
    $(foreach d,$(SENS_TREE_DEPTHS),row;scene=$s;study=tree_depth;value=$d;file=$(call sens_sim,$s,$(call \
      sens_render,$(call sens_depth_kd,$d)) $(call hybrid_for,$(SENS_SIZE)),auto)) \
    $(foreach r,$(SENS_RESOLUTIONS),row;scene=$s;study=resolution;value=$r;file=$(call sens_sim,$s,$(call \
      sens_res_render,$r) $(call hybrid_for,$(SENS_SIZE)),auto)))
$(eval $(call study_rule,sensitivity))
endif

# --- calibration: the kd-tree setting closest to the paper's single column --
# A grid at CAL_WIDTH x CAL_HEIGHT ranked by the distance of our single-cache
# column to the paper's (calibration-grid, which writes best.txt); then the
# best CAL_BEST settings again at CAL_FINAL_WIDTH x CAL_FINAL_HEIGHT, in a
# second make since which they are is known only after the grid.
cal_grid := $(foreach d,$(CAL_TREE_DEPTHS),$(foreach c,$(CAL_COSTS),$(foreach e,$(CAL_EMPTY_BONUSES),$d:$c:$e)))
cal_kd = $(call kd_options,$(word 1,$(subst :, ,$1)),$(word 2,$(subst :, ,$1)),$(word 3,$(subst :, ,$1)),$(word 4,$(subst :, ,$1)))
cal_rows = $(foreach g,$3,$(foreach s,$(CAL_SCENES),$(foreach z,$(SIZES),row;phase=$4;setting=$g;scene=$s;size=$z;file=$(call \
  sim,calibration,$(call trace,$s,$(call render_options,$1,$2,$(FRAME),$(call cal_kd,$g)) $(call \
  hybrid_for,$z)),--size $z --block $(BLOCK) --assoc 1 --scheme single$(comma)split --split-level auto))))
cal_params = $(common_params) param;cal_width=$(CAL_WIDTH) param;cal_height=$(CAL_HEIGHT) param;cal_best=$(CAL_BEST)
calibration-grid_figures := best.txt
calibration_figures := calibration.png
CAL_FINAL ?=
ifneq ($(call wanted,calibration)$(call wanted,calibration-grid),)
calibration-grid_lines := $(cal_params) $(call cal_rows,$(CAL_WIDTH),$(CAL_HEIGHT),$(cal_grid),grid)
$(eval $(call study_rule,calibration-grid))
ifneq ($(CAL_FINAL),)
calibration_lines := $(calibration-grid_lines) param;cal_final_width=$(CAL_FINAL_WIDTH) \
  param;cal_final_height=$(CAL_FINAL_HEIGHT) \
  $(call cal_rows,$(CAL_FINAL_WIDTH),$(CAL_FINAL_HEIGHT),$(CAL_FINAL),final)
$(eval $(call study_rule,calibration))
else
# Under `all`, after the others: its final traces may be theirs (a make of its own).
calibration: calibration-grid $(if $(filter all,$(goals)),$(filter-out calibration,$(ALL_TARGETS)))
	@best="$$(cat $(OUT)/calibration-grid/best.txt)"; \
	  if [ -z "$$best" ]; then echo "calibration: $(OUT)/calibration-grid/best.txt is empty (CAL_BEST=$(CAL_BEST))" >&2; exit 1; fi; \
	  $(MAKE) --no-print-directory -f $(MK_FILE) calibration CAL_FINAL="$$best"
endif
endif

# --- frames: the gain per sampled animation frame ---------------------------
frames_figures := frames.png
ifneq ($(call wanted,frames),)
frame_numbers := $(shell seq $(FRAME_FIRST) $(FRAME_STEP) $(FRAME_LAST))
frames_lines := $(common_params) param;frame_width=$(FRAME_WIDTH) param;frame_height=$(FRAME_HEIGHT) \
  param;frame_step=$(FRAME_STEP) \
  $(foreach s,$(FRAME_SCENES),$(foreach f,$(frame_numbers),$(foreach z,$(FRAME_SIZES),row;scene=$s;size=$z;frame=$f;file=$(call \
  sim,frames,$(call trace,$s,$(call render_options,$(FRAME_WIDTH),$(FRAME_HEIGHT),$f,$(kd_default)) $(call \
  hybrid_for,$z)),--size $z --block $(BLOCK) --assoc 1 --scheme single$(comma)split --split-level auto))))
$(eval $(call study_rule,frames))
endif

# --- sampling: sampled renders and simulations against the full run --------
# Every run is timed (scripts/timed-run.py: wall and user + sys of render and
# simulation). The full run renders the trace that windows and sets sample
# (their render time is the full one); rows renders a sampled trace of its own.
sampling_figures := sampling.png
ifneq ($(call wanted,sampling),)
samp_runs := $(OUT)/sampling/runs
samp_render = $(TRACER) render $(call scene_arg,$1) -q $(render_default) $(call hybrid_for,$2)
samp_sim = $(CACHESIM) run --size $1 --block $(BLOCK) --assoc 1 --scheme single$(comma)split --split-level auto
samp_method_render = $(if $(filter rows,$1),--sample-rows 1/$2 --sample-seed $3)
samp_method_sim = $(if $(filter windows,$1),--sample-windows 1/$2 --window-records $(SAMPLING_WINDOW_RECORDS) \
  --sample-seed $3)$(if \
  $(filter sets,$1),--sample-sets 1/$2 --sample-seed $3)
# $(call samp_full,SCENE,SIZE): the full run's CSV (its trace beside it, .din.zst).
samp_full = $(call define_samp,$(samp_runs)/full-$(call hash_text,$(tracer_hash) $(cachesim_hash) $(call \
  scene_hash,$1) $(call samp_render,$1,$2) $(call samp_sim,$2)).csv,--render '$(call samp_render,$1,$2)' \
  --keep-trace --simulate '$(call samp_sim,$2)',,full $1 $2)
# $(call samp_run,SCENE,SIZE,METHOD,RATE,SEED): one sampled run's CSV.
samp_run = $(if $(filter rows,$3),$(call define_samp,$(samp_runs)/rows-$(call hash_text,$(tracer_hash) \
  $(cachesim_hash) $(call scene_hash,$1) $(call samp_render,$1,$2) $(call samp_method_render,$3,$4,$5) \
  $(call samp_sim,$2)).csv,--render '$(call samp_render,$1,$2) $(call samp_method_render,$3,$4,$5)' \
  --simulate '$(call samp_sim,$2)',,rows 1/$4 seed $5 $1 $2),$(call define_samp,$(samp_runs)/$3-$(call \
  hash_text,$(call samp_full,$1,$2) $(cachesim_hash) $(call samp_method_sim,$3,$4,$5)).csv,--simulate \
  '$(call samp_sim,$2) $(call samp_method_sim,$3,$4,$5)',$(call samp_full,$1,$2),$3 1/$4 seed $5 $1 $2))
define_samp = $(if $(defined_$1),,$(eval $(call samp_rule,$1,$2,$3,$4))$(eval defined_$1 := 1))$1
# The trace of a run: a full run's own, or its full run's for windows and sets.
samp_trace = $(patsubst %.csv,%.din.zst,$(or $1,$2))
define samp_rule
$1: $3 $(MK_DIR)/timed-run.py | $(samp_runs)/.dir
	@echo "sampling: $4" >&2
	@$(RUN) $(PYTHON) $(MK_DIR)/timed-run.py --out $$@ --trace $(call samp_trace,$3,$1) $2
endef
sampling_lines := $(common_params) param;tracer=$(TRACER) \
  $(foreach s,$(SAMPLING_SCENES),$(foreach z,$(SAMPLING_SIZES),row;scene=$s;size=$z;method=full;rate=1;seed=0;file=$(call \
  samp_full,$s,$z) $(foreach m,$(SAMPLING_METHODS),$(foreach r,$(SAMPLING_RATES),$(foreach e,$(SAMPLING_SEEDS),row;scene=$s;size=$z;method=$m;rate=$r;seed=$e;file=$(call \
  samp_run,$s,$z,$m,$r,$e))))))
$(eval $(call study_rule,sampling))
endif

# The traces this make renders (progress: which of them this one is).
to_render := $(filter-out $(wildcard $(all_traces)),$(all_traces))

clean:
	rm -rf $(OUT)/traces $(addprefix $(OUT)/,$(ALL_TARGETS) calibration-grid)
