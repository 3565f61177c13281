# Experiments around Table 1 of Nah, Heo, Park, Han, "A Split Node Cache
# Scheme for Fast Ray Tracing" (RT'08): the table as the paper lays it out,
# and the studies that explain it. docs/guide/studies.md ("The experiment
# Makefile") lists the targets and their outputs.
#
#   make -f scripts/experiments.mk                   # or help: the targets, nothing run
#   make -f scripts/experiments.mk table1            # or: make -f scripts/table1.mk
#   make -f scripts/experiments.mk -j2 all
#   make -f scripts/experiments.mk table1 SCENES=robot WIDTH=64 HEIGHT=48
#   make -f scripts/experiments.mk -j64 RUN="srun --ntasks=1 --cpus-per-task=2" frames
#
# Rebuilds are decided by content, not by file times: a trace's file name is a
# hash of everything that changes its records (the tracer binary, every file
# of the scene's folder, the tracer options), a simulation's name a hash of
# its trace's name, the cachesim binary and its options. A trace exists or is
# rendered; it is never stale, and never rendered twice. Traces that differ
# only in their layout are written by one render (scripts/render-layouts.sh).
# By default no study keeps its traces: each simulation runs inside the render
# that would write its trace (tracer render --simulate, cachesim run's options
# and report, no text written or read back), all the simulations of a group of
# layouts in one render, and the run's CSV gets RUN.csv.trace.json beside it
# (the trace's header and totals, what the reports read of a trace).
# KEEP_TRACES=1 writes every trace under $(OUT)/traces and runs cachesim on it
# instead; the studies' tables are the same bytes either way.
# Each target's list of inputs (its manifest) is rewritten only when its
# content changes, so a table is remade exactly when its set of inputs or one
# of them changes.
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
# Built kd-trees and BVHs kept between renders (tracer --tree-cache): the
# renders of one scene and tree build load the tree the first one built.
# Never part of a hash: a cold or warm cache gives the same files (the
# tracer's traces do not depend on it). TREE_CACHE= renders without one.
TREE_CACHE ?= $(OUT)/tree-cache
tree_cache_option = $(if $(TREE_CACHE),--tree-cache $(TREE_CACHE))

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
# The reading of the paper's open choices table1 uses (docs/REPRODUCTION.md):
# each axis below, or INTERPRETATION=AXIS=VALUE,... naming some of them
# (axes: size base loads k depth tcost icost bonus leaf rays lights frame).
#   SIZE_MEANING  half: a row's size is the total, split half and half; each:
#                 each cache has the row's size; highk: the high cache holds
#                 the levels < K (8 << K bytes), the low cache the row's size
#   BASELINE      the layout of the "without" column: hybrid (the split's own
#                 trace), dfl, bfl or veb
#   HIGH_LOADS    free: the high cache's loads are not misses; counted
#   SPLIT_LEVEL   K: auto (the most levels that fit the high cache) or a number
#   LEAF_SIZE     a node of at most this many triangles is a leaf (0: SAH only)
#   RAYS          whitted, primary+shadow or primary
#   LIGHTS        all, or first (shadow rays to the scene's first light only)
SIZE_MEANING ?= half
BASELINE ?= hybrid
HIGH_LOADS ?= free
SPLIT_LEVEL ?= auto
LEAF_SIZE ?= 0
RAYS ?= whitted
LIGHTS ?= all
INTERPRETATION ?=
# 1: write every trace and simulate it with cachesim run; 0: simulate inside
# the render, no trace kept (the header at the top).
KEEP_TRACES ?= 0
# zstd level of the traces the studies write (results do not depend on it):
# a render of BART Kitchen at 400x300 writing three traces takes 0.76x the
# CPU at level 1 as at level 3, for traces of 1.1x the bytes.
TRACE_ZSTD_LEVEL ?= 1

# --- Studies ------------------------------------------------------------------
# Acceleration structures (the accel target): Table 1's grid for each
# structure and layout. TREELET_BYTES: the treelet layout's treelet size.
ACCEL_SCENES ?= robot kitchen
ACCEL_KINDS ?= kdtree bvh2 bvh4 bvh8 cwbvh8
ACCEL_LAYOUTS ?= dfl bfl veb treelet
ACCEL_SIZES ?= $(SIZES)
ACCEL_BLOCKS ?= 8 32 64
ACCEL_ASSOCS ?= 1 4
TREELET_BYTES ?= 64
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
# Interpretations: a grid of readings at INTERP_WIDTH x INTERP_HEIGHT over
# INTERP_SCENES (every combination of the lists below; a tree setting is
# DEPTH:TRAVERSAL:INTERSECTION:EMPTYBONUS:LEAFSIZE, a ray set RAYS:LIGHTS),
# then the best INTERP_BEST
# and the default reading at INTERP_FINAL_WIDTH x INTERP_FINAL_HEIGHT over
# INTERP_FINAL_SCENES.
INTERP_SCENES ?= robot kitchen
INTERP_WIDTH ?= 200
INTERP_HEIGHT ?= 150
INTERP_SIZE_MEANINGS ?= half each highk
INTERP_BASELINES ?= hybrid dfl bfl veb
# Counted loads add at most the 2^K - 1 high nodes once per frame (Kitchen
# 200x150 4 KB: 162 of 18.9 M fetches): counted is an axis, left out of the
# default grid.
INTERP_HIGH_LOADS ?= free
INTERP_SPLIT_LEVELS ?= auto 6
INTERP_TREES ?= default:1:1.5:0.2:0 20:1:1.5:0.2:0 default:1:1.5:0.2:2
INTERP_RAY_SETS ?= whitted:all whitted:first primary+shadow:all primary:all
INTERP_FRAMES ?= 0
INTERP_BEST ?= 8
INTERP_FINAL_SCENES ?= robot kitchen forest
INTERP_FINAL_WIDTH ?= $(WIDTH)
INTERP_FINAL_HEIGHT ?= $(HEIGHT)
# Replacement policies: the single cache under each of POLICY_SINGLE and the
# split with each of POLICY_SPLIT in its low cache, Table 1's sizes at
# POLICY_ASSOCS ways and POLICY_BLOCKS-byte blocks, for each structure of
# POLICY_ACCELS, at POLICY_WIDTH x POLICY_HEIGHT (opt keeps 8 bytes a fetch
# of each block size: Kitchen at 400x300, 76 M fetches, about 0.7 GB).
POLICY_SCENES ?= robot kitchen
POLICY_ACCELS ?= kdtree bvh2
POLICY_SIZES ?= $(SIZES)
POLICY_BLOCKS ?= 8 64
POLICY_ASSOCS ?= 1 4 8
POLICY_SINGLE ?= lru plru srrip drrip opt
POLICY_SPLIT ?= lru drrip opt
POLICY_WIDTH ?= 400
POLICY_HEIGHT ?= 300
# Treelet prefetching (the prefetch target): on one trace per scene,
# structure, integrator and treelet size (--layout treelet, treelets of each
# of PREFETCH_TREELET_BYTES), Table 1's sizes (SIZES) at PREFETCH_ASSOCS ways
# and PREFETCH_BLOCK-byte blocks, single and split (K auto, high cache
# retained), with no prefetch, the treelet prefetcher (whole treelet) and,
# single only, Dinero IV's tagged prefetch. Path tracing at PREFETCH_SPP
# samples per pixel. At 400x300 the whole study took 16.8 minutes of wall
# time (409 s of CPU) with -j2 on the 2-core machine shared with other work,
# 200x150 3.1 minutes (docs/guide/studies.md).
PREFETCH_SCENES ?= robot kitchen
PREFETCH_ACCELS ?= kdtree bvh2 cwbvh8
PREFETCH_INTEGRATORS ?= whitted path
PREFETCH_SPP ?= 1
PREFETCH_WIDTH ?= 400
PREFETCH_HEIGHT ?= 300
PREFETCH_BLOCK ?= 64
PREFETCH_ASSOCS ?= 1 4
PREFETCH_TREELET_BYTES ?= 256 1024
# Rays in flight: traversal units of INFLIGHT_RAYS ray slots each, every
# unit its own node caches of each size of SIZES (per unit), and a second
# level shared by the units behind them. Pixels dealt to the units in 8x8
# tiles (tiled pixel order, 64 pixels a run) round robin.
INFLIGHT_SCENES ?= robot kitchen
INFLIGHT_WIDTH ?= 200
INFLIGHT_HEIGHT ?= 150
INFLIGHT_RAYS ?= 1 4 16 32 128
INFLIGHT_UNITS ?= 1 4 16
INFLIGHT_L2_SIZE ?= 256k
INFLIGHT_L2_BLOCK ?= 64
INFLIGHT_L2_ASSOC ?= 8

scene_robot := $(SHARED)/scenes/bart/robots/Robot.aff
scene_kitchen := $(SHARED)/scenes/bart/kitchen/kitchen.aff
# The paper's Fairy Forest is not available; the built-in forest stands in.
scene_forest := forest
# The scenes of scripts/cycles/scenes.py, which Blender Cycles renders too
# (scripts/test-cycles.sh): AFF files it writes under $(OUT)/scenes, each
# hashed as the script that writes it.
CYCLES_SCENES := sphere cornell mirror glass
$(foreach s,$(CYCLES_SCENES),$(eval scene_$s := $(OUT)/scenes/$s.aff)$(eval scene_hash_$s = $$(call \
  file_hash,$(MK_DIR)/cycles/scenes.py)))
$(OUT)/scenes/%.aff: $(MK_DIR)/cycles/scenes.py | $(OUT)/scenes/.dir
	@$(PYTHON) $(MK_DIR)/cycles/scenes.py $* $@

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
# Remembered by text (a study names the same trace or run many times).
hash_key = hash_of_$(subst :,~,$(subst $(space),^,$1))
hash_text = $(or $($(call hash_key,$1)),$(eval $(call hash_key,$1) := $(call checked_hash,$(shell \
  printf '%s' '$1' | sha256sum | cut -c1-16),the options '$1'))$($(call hash_key,$1)))
file_hash = $(call checked_hash,$(shell sha256sum < '$1' | cut -c1-16),$1)

# Hashes are computed on first use only, so `make clean` needs no build.
need_program = $(if $(wildcard $1),,$(error $1 not found: build first (scripts/setup.sh)))
tracer_hash = $(or $(tracer_hash_value),$(call need_program,$(TRACER))$(eval tracer_hash_value := $(call file_hash,$(TRACER)))$(tracer_hash_value))
cachesim_hash = $(or $(cachesim_hash_value),$(call need_program,$(CACHESIM))$(eval cachesim_hash_value := $(call file_hash,$(CACHESIM)))$(cachesim_hash_value))

# A file scene is every file of its folder (an AFF file includes others); a
# built-in scene is its name, its geometry being part of the tracer binary.
scene_arg = $(or $(scene_$1),$(error unknown scene '$1' (expected robot, kitchen, forest, $(call \
  join_commas,$(CYCLES_SCENES)))))
scene_hash = $(or $(scene_hash_$1),$(eval scene_hash_$1 := $(call compute_scene_hash,$1))$(scene_hash_$1))
compute_scene_hash = $(if $(findstring /,$(call scene_arg,$1)),$(if $(wildcard $(scene_$1)),$(call checked_hash,$(shell \
  cd '$(dir $(scene_$1))' && find . -type f | LC_ALL=C sort | xargs -r sha256sum | sha256sum | cut -c1-16),scene $1),$(error scene $1: $(scene_$1) not found (SHARED=$(SHARED)))),builtin-$(scene_$1))

# Bytes of a size such as 16k or 1m, and half of it (the paper's split).
# Remembered by size (a study asks for the same few many times).
size_bytes = $(or $(bytes_of_$1),$(eval bytes_of_$1 := $(or $(shell echo $$(( $(subst k,*1024,$(subst \
  m,*1048576,$1)) ))),$(error bad size '$1' (expected e.g. 4k))))$(bytes_of_$1))
half_size = $(or $(half_of_$1),$(eval half_of_$1 := $(shell echo $$(( $(call size_bytes,$1) / 2 ))))$(half_of_$1))

# kd-tree build options: DEPTHLIMIT TRAVERSAL INTERSECTION EMPTYBONUS.
kd_options = --traversal-cost $2 --intersection-cost $3 --empty-bonus $4$(if $(filter default,$1),, --tree-depth $1)
kd_default := $(call kd_options,$(TREE_DEPTH),$(TRAVERSAL_COST),$(INTERSECTION_COST),$(EMPTY_BONUS))
# Render options: WIDTH HEIGHT FRAME KD-OPTIONS.
render_options = --width $1 --height $2 --max-depth $(DEPTH) --frame $3 $4
render_default := $(call render_options,$(WIDTH),$(HEIGHT),$(FRAME),$(kd_default))
hybrid_for = --layout hybrid --high-size $(call half_size,$1)

# --- An interpretation of the paper: one word of twelve fields -----------------
# SIZE:BASE:LOADS:K:DEPTH:TRAVERSAL:INTERSECTION:EMPTYBONUS:LEAF:RAYS:LIGHTS:FRAME
# (the axes at the top of this file; docs/REPRODUCTION.md says what each does).
interp_axes := size base loads k depth tcost icost bonus leaf rays lights frame
interp_given := $(subst $(comma), ,$(INTERPRETATION))
$(foreach g,$(interp_given),$(if $(filter $(firstword $(subst =, ,$g)),$(interp_axes)),,$(error \
  INTERPRETATION: unknown axis in '$g' (expected AXIS=VALUE, AXIS one of $(interp_axes)))))
interp_pick = $(or $(patsubst $1=%,%,$(filter $1=%,$(interp_given))),$2)
interp_default := $(call interp_pick,size,$(SIZE_MEANING)):$(call interp_pick,base,$(BASELINE)):$(call \
  interp_pick,loads,$(HIGH_LOADS)):$(call interp_pick,k,$(SPLIT_LEVEL)):$(call interp_pick,depth,$(TREE_DEPTH)):$(call \
  interp_pick,tcost,$(TRAVERSAL_COST)):$(call interp_pick,icost,$(INTERSECTION_COST)):$(call \
  interp_pick,bonus,$(EMPTY_BONUS)):$(call interp_pick,leaf,$(LEAF_SIZE)):$(call interp_pick,rays,$(RAYS)):$(call \
  interp_pick,lights,$(LIGHTS)):$(call interp_pick,frame,$(FRAME))
i_size = $(word 1,$(subst :, ,$1))
i_base = $(word 2,$(subst :, ,$1))
i_loads = $(word 3,$(subst :, ,$1))
i_k = $(word 4,$(subst :, ,$1))
i_leaf = $(word 9,$(subst :, ,$1))
i_rays = $(word 10,$(subst :, ,$1))
i_lights = $(word 11,$(subst :, ,$1))
i_frame = $(word 12,$(subst :, ,$1))
interp_check = $(if $(filter 12,$(words $(subst :, ,$1))),,$(error interpretation '$1': expected 12 fields \
  SIZE:BASE:LOADS:K:DEPTH:TRAVERSAL:INTERSECTION:EMPTYBONUS:LEAF:RAYS:LIGHTS:FRAME))$(if $(filter half each \
  highk,$(call i_size,$1)),,$(error interpretation '$1': size is half, each or highk))$(if $(filter hybrid dfl bfl \
  veb,$(call i_base,$1)),,$(error interpretation '$1': base is hybrid, dfl, bfl or veb))$(if $(filter free \
  counted,$(call i_loads,$1)),,$(error interpretation '$1': loads is free or counted))$(if $(filter whitted \
  primary+shadow primary,$(call i_rays,$1)),,$(error interpretation '$1': rays is whitted, primary+shadow or \
  primary))$(if $(filter all first,$(call i_lights,$1)),,$(error interpretation '$1': lights is all or \
  first))$(if $(and $(filter highk,$(call i_size,$1)),$(filter auto,$(call i_k,$1))),$(error interpretation \
  '$1': size highk sizes the high cache by K, so K must be a number))
# Bytes of the high and the low cache for a row of size $2.
interp_high = $(if $(filter half,$(call i_size,$1)),$(call half_size,$2),$(if $(filter each,$(call \
  i_size,$1)),$(call size_bytes,$2),$(call size_bytes,$(call k_bytes,$(call i_k,$1)))))
k_bytes = $(or $(k_bytes_$1),$(eval k_bytes_$1 := $(shell echo $$(( 8 << $1 ))))$(k_bytes_$1))
interp_low = $(if $(filter half,$(call i_size,$1)),$(call half_size,$2),$(call size_bytes,$2))
# Tracer options of a reading at width $2, height $3 (the default's are render_default's).
interp_kd = $(call kd_options,$(word 5,$(subst :, ,$1)),$(word 6,$(subst :, ,$1)),$(word 7,$(subst \
  :, ,$1)),$(word 8,$(subst :, ,$1)))$(if $(filter 0,$(call i_leaf,$1)),, --leaf-size $(call i_leaf,$1))
interp_render = $(call render_options,$2,$3,$(call i_frame,$1),$(call interp_kd,$1)$(if $(filter \
  whitted,$(call i_rays,$1)),, --rays $(call i_rays,$1))$(if $(filter all,$(call i_lights,$1)),, --lights first))
interp_layout = --layout hybrid $(if $(filter auto,$(call i_k,$1)),--high-size $(call interp_high,$1,$2),--split-level \
  $(call i_k,$1))
# cachesim options of the split's run, which gives the single over the same
# trace too (the hybrid baseline): --size is the single's, --high-size and
# --low-size the split's when they are not half the row each.
interp_split_options = --size $2 --block $(BLOCK) --assoc 1 --scheme single$(comma)split --split-level $(call \
  i_k,$1)$(if $(filter half,$(call i_size,$1)),, \
  --high-size $(call interp_high,$1,$2) --low-size $(call interp_low,$1,$2))$(if $(filter counted,$(call \
  i_loads,$1)), --count-loads)
# $(call interp_files,TARGET,WORD,SCENE,SIZE,WIDTH,HEIGHT): single=CSV;split=CSV of one cell.
interp_split_file = $(call sim,$1,$(call trace,$3,$(call interp_render,$2,$5,$6) $(call interp_layout,$2,$4)),$(call \
  interp_split_options,$2,$4))
# The single over another layout: one run for every size of SIZES.
interp_single_file = $(if $(filter hybrid,$(call i_base,$2)),$(call interp_split_file,$1,$2,$3,$4,$5,$6),$(call \
  sim,$1,$(call trace,$3,$(call interp_render,$2,$5,$6) --layout $(call i_base,$2)),--size $(call \
  join_commas,$(SIZES)) --block $(BLOCK) --assoc 1 --scheme single))
interp_files = $(call interp_check,$2)single=$(call interp_single_file,$1,$2,$3,$4,$5,$6);split=$(call \
  interp_split_file,$1,$2,$3,$4,$5,$6)

# $(call trace,SCENE,TRACER-OPTIONS): the trace of that scene rendered with
# those options; its rule is defined on first use. Traces that differ only in
# their layout (--layout, --split-level, --high-size) form a group, rendered
# once by scripts/render-layouts.sh, which writes every missing trace of the
# group from one render: the group's members are complete when the recipe
# runs, after make has read every study.
# A BVH's trace (--accel) is extended din: its records carry the node's size.
trace = $(call named_trace,$1,$2 --zstd-level $(TRACE_ZSTD_LEVEL))
named_trace = $(call define_trace,$(TRACES)/$1-$(call hash_text,$(tracer_hash) $(call scene_hash,$1) $2).$(if \
  $(findstring --accel ,$2),xdin,din).zst,$1,$2)
# Without KEEP_TRACES=1 a trace is only a name its simulations refer to.
define_trace = $(if $(defined_$1),,$(eval defined_$1 := 1)$(eval trace_scene_$1 := $2)$(eval trace_options_$1 := \
  $3)$(if $(filter 1,$(KEEP_TRACES)),$(call define_member,$1,$2,$3,$(call trace_group,$2,$3),$1=$(call \
  layout_name,$3))))$1
# $(call define_member,FILE,SCENE,OPTIONS,GROUP,MEMBER): the first file of a
# group (a trace, or a run simulated in the render) leads it: its recipe
# renders the whole group, and the others wait for it (they render only when
# their file went missing). MEMBER is what scripts/render-layouts.sh makes of it.
define_member = $(eval $(call trace_rule,$1,$2,$3,$4,$(group_leader_$4)))$(if \
  $(group_leader_$4),,$(eval group_leader_$4 := $1)$(eval all_groups += $4))$(eval group_files_$4 += $1)$(eval \
  group_members_$4 += $5)
# Tracer options with each layout option joined to its value (--layout=bfl).
layout_joined = $(subst --layout$(space),--layout=,$(subst --split-level$(space),--split-level=,$(subst \
  --high-size$(space),--high-size=,$1)))
layout_words = $(filter --layout=% --split-level=% --high-size=%,$(call layout_joined,$1))
render_words = $(filter-out --layout=% --split-level=% --high-size=%,$(call layout_joined,$1))
# The name tracer render gives the layout in {layout}: dfl, bfl, veb, treelet, hybrid-kK, hybrid-SIZE.
layout_name = $(or $(patsubst --split-level=%,hybrid-k%,$(filter --split-level=%,$(call \
  layout_words,$1))),$(patsubst --high-size=%,hybrid-%,$(filter --high-size=%,$(call \
  layout_words,$1))),$(patsubst --layout=%,%,$(filter --layout=%,$(call layout_words,$1))),dfl)
trace_group = $(call hash_text,group $(tracer_hash) $(call scene_hash,$1) $(call render_words,$2))
# $(call trace_rule,FILE,SCENE,OPTIONS,GROUP,LEADER): LEADER is empty for the leader.
define trace_rule
$1: | $(TRACES)/.dir $(dir $1).dir $5
	@$(if $5,test -f $$@ || )echo "render [$$(words $$(wildcard $$(to_render)) x) of $$(words $$(to_render))] \
	  $2 $(call render_words,$3), layouts: $$(sort $$(foreach m,$$(group_members_$4),$$(word 2,$$(subst =, ,$$m))))" >&2
	@$(if $5,test -f $$@ || )$(RUN) $(MK_DIR)/render-layouts.sh $(TRACES)/.group-$4.lock $(TRACER) $(call \
	  scene_arg,$2) -q $(tree_cache_option) $(call render_words,$3) -- $$(group_members_$4)
endef

# $(call sim,TARGET,TRACE,CACHESIM-OPTIONS): cachesim's CSV for that trace,
# run on the written trace (KEEP_TRACES=1) or inside its render: a member of
# the trace's group whose options travel with spaces written as ^.
sim = $(if $(filter 1,$(KEEP_TRACES)),$(call define_sim,$(OUT)/$1/runs/$(call hash_text,$(cachesim_hash) $2 \
  $3).csv,$2,$3),$(call define_sim_in_render,$(OUT)/$1/runs/$(call hash_text,in-render $(cachesim_hash) $2 \
  $3).csv,$2,$3))
define_sim_in_render = $(if $(defined_$1),,$(eval defined_$1 := 1)$(call define_member,$1,$(trace_scene_$2),$(call \
  trace_options_of,$2),$(call trace_group,$(trace_scene_$2),$(trace_options_$2)),$1=$(call \
  layout_name,$(trace_options_$2))=$(subst $(space),^,$(strip $3))))$1
trace_options_of = $(or $(trace_options_$1),$(error $1: not a trace of $$(call trace,...)))
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
# Written by make itself ($(file)): a study's lines can exceed what one
# shell command line may hold.
define newline


endef
# A dry run (make -n) writes nothing, not even through $(file): it says
# which manifest it would write.
dry_run := $(findstring n,$(firstword -$(MAKEFLAGS)))
define manifest_rule
$(OUT)/$1/manifest.txt: FORCE | $(OUT)/$1/.dir
	@$$(if $(dry_run),echo "write $$@ ($$(words $$($1_lines)) lines)",$$(file >$$@.tmp,$$(subst \
	  $$(newline)$$(space),$$(newline),$$(foreach line,$$($1_lines),$$(line)$$(newline)))))
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
# Without a target: help, not every study (thousands of renders and
# simulations at the defaults); table1.mk makes table1 its default.
.DEFAULT_GOAL := $(or $(.DEFAULT_GOAL),help)
goals := $(or $(MAKECMDGOALS),$(.DEFAULT_GOAL))
wanted = $(filter $1 all,$(goals))

# RUN's program (srun on a Slurm cluster) must exist before any recipe runs,
# else each would fail with the shell's "srun: not found".
ifneq ($(strip $(RUN)),)
ifneq ($(filter-out help clean,$(goals)),)
$(if $(shell command -v '$(firstword $(RUN))' 2>/dev/null),,$(error RUN="$(strip $(RUN))": no program \
  '$(firstword $(RUN))' on PATH (Slurm's srun where RUN is a cluster's launcher): install it, or leave RUN \
  empty to run here))
endif
endif

.PHONY: help all table1 baselines assoc levels sensitivity calibration calibration-grid interpretations \
  interpretations-grid frames sampling accel inflight policies prefetch workloads convergence clean FORCE
.DELETE_ON_ERROR:

# Every study; `all` makes them (a new study adds its target here and its section below).
ALL_TARGETS := table1 baselines assoc levels sensitivity calibration interpretations frames sampling accel inflight \
  policies prefetch workloads convergence
all: $(ALL_TARGETS)

# Each study's line is its section's "# --- NAME: ..." heading below (or in path-tracing.mk).
help:
	@echo 'make -f $(MK_FILE) TARGET [VARIABLE=VALUE ...]: each study writes $(OUT)/TARGET/ (docs/guide/studies.md)'
	@echo 'Targets:'
	@$(foreach t,$(ALL_TARGETS),printf '  %-16s %s\n' '$t' "$$(sed -n 's/^# --- $t: \(.*[^ -]\) *-*$$/\1/p' \
	  $(MK_FILE) $(MK_DIR)/path-tracing.mk)";)
	@printf '  %-16s %s\n' all 'every study above (a long run at the defaults)' \
	  clean 'remove $(OUT)/traces and the studies'"'"' outputs' help 'this list (also: no target)'
	@echo 'Variables (the comments at the top of $(MK_FILE) describe them): WIDTH HEIGHT SCENES SIZES BLOCK'
	@echo '  BUILD SHARED OUT RUN (e.g. RUN="srun --ntasks=1 --cpus-per-task=2") KEEP_TRACES INTERPRETATION'

%/.dir:
	@mkdir -p $(@D) && touch $@

# --- table1: Robot, Kitchen, forest; 4/8/16 KB; single and split -----------
# The reading used (interp_default: the axes at the top, or INTERPRETATION);
# by default "without" is the single cache over the same hybrid-layout trace
# as "with". A second table gives CLOSEST_INTERPRETATION, the reading the
# interpretations study found closest to the paper (docs/REPRODUCTION.md;
# empty: none): half and half, BFL "without", kd-tree depth limit 20.
CLOSEST_INTERPRETATION ?= half:bfl:free:auto:20:1:1.5:0.2:0:whitted:all:0
table1_figures := table1.png
ifneq ($(call wanted,table1),)
table1_word_used := $(interp_default)
table1_word_closest := $(CLOSEST_INTERPRETATION)
table1_readings := used $(if $(filter-out $(interp_default),$(CLOSEST_INTERPRETATION)),closest)
table1_lines := $(common_params) param;interpretation=$(interp_default) \
  $(foreach r,$(table1_readings),$(foreach s,$(SCENES),$(foreach z,$(SIZES),row;reading=$r;interp=$(table1_word_$r);scene=$s;size=$z;$(call \
  interp_files,table1,$(table1_word_$r),$s,$z,$(WIDTH),$(HEIGHT)))))
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

# --- accel: Table 1's grid for each acceleration structure and layout -----
# Each structure (ACCEL_KINDS) in each layout (ACCEL_LAYOUTS) under one
# node cache (single) of every size, block and associativity; and in the
# hybrid layout sized for each size's high cache, single against split
# (split level auto). A kd-tree's options and traces are table1's.
accel_figures := accel.png
ifneq ($(call wanted,accel),)
# --treelet-bytes, when not the tracer's default of 64, goes on every render of
# a structure, so the treelet trace stays one more layout of the same render
# (scripts/render-layouts.sh) and, at the default, the kd-tree's traces are
# table1's.
accel_render = $(render_default)$(if $(filter kdtree,$1),, --accel $1)$(if $(filter 64,$(TREELET_BYTES)),, \
  --treelet-bytes $(TREELET_BYTES))
accel_grid = --block $(call join_commas,$(ACCEL_BLOCKS)) --assoc $(call join_commas,$(ACCEL_ASSOCS))
accel_layout = --layout $1
accel_row = row;scene=$1;accel=$2;layout=$3;trace=$4;file=$(call sim,accel,$4,$5)
accel_lines := $(common_params) param;treelet_bytes=$(TREELET_BYTES) \
  $(foreach s,$(ACCEL_SCENES),$(foreach a,$(ACCEL_KINDS), \
    $(foreach l,$(ACCEL_LAYOUTS),$(call accel_row,$s,$a,$l,$(call trace,$s,$(call accel_render,$a) $(call \
      accel_layout,$l)),--size $(call join_commas,$(ACCEL_SIZES)) $(accel_grid) --scheme single)) \
    $(foreach z,$(ACCEL_SIZES),$(call accel_row,$s,$a,hybrid,$(call trace,$s,$(call accel_render,$a) $(call \
      hybrid_for,$z)),--size $z $(accel_grid) --scheme single$(comma)split --split-level auto))))
$(eval $(call study_rule,accel))
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

# A second phase is worked out from its grid's best.txt: a dry run without
# that file says so and stops there (make -n runs a recipe line that
# refers to $(MAKE); the shell's `exit 0` ends it before the sub-make).
second_phase_dry_run = $(if $(and $(dry_run),$(if $(wildcard $2),,none)),echo "$1: its final phase is decided \
  by $2 (written by the grid): not known in a dry run"; exit 0; )

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
	@$(call second_phase_dry_run,calibration,$(OUT)/calibration-grid/best.txt)best="$$(cat $(OUT)/calibration-grid/best.txt)"; \
	  if [ -z "$$best" ]; then echo "calibration: $(OUT)/calibration-grid/best.txt is empty (CAL_BEST=$(CAL_BEST))" >&2; exit 1; fi; \
	  $(MAKE) --no-print-directory -f $(MK_FILE) calibration CAL_FINAL="$$best"
endif
endif

# --- interpretations: which reading of the paper's open choices reproduces it
# Every combination of the INTERP_* lists at INTERP_WIDTH x INTERP_HEIGHT
# (interpretations-grid, which writes best.txt), ranked by the mean absolute
# difference to the paper over the BART cells; then the best INTERP_BEST and
# the default reading at INTERP_FINAL_WIDTH x INTERP_FINAL_HEIGHT, in a second
# make as calibration does. A size-by-K reading needs a number for K.
interp_grid := $(foreach t,$(INTERP_TREES),$(foreach r,$(INTERP_RAY_SETS),$(foreach \
  f,$(INTERP_FRAMES),$(foreach z,$(INTERP_SIZE_MEANINGS),$(foreach k,$(if $(filter highk,$z),$(filter-out \
  auto,$(INTERP_SPLIT_LEVELS)),$(INTERP_SPLIT_LEVELS)),$(foreach b,$(INTERP_BASELINES),$(foreach \
  o,$(INTERP_HIGH_LOADS),$z:$b:$o:$k:$t:$r:$f)))))))
# $(call interp_rows,WIDTH,HEIGHT,WORDS,PHASE,SCENES)
interp_rows = $(foreach w,$3,$(foreach s,$5,$(foreach z,$(SIZES),row;phase=$4;interp=$w;scene=$s;size=$z;$(call \
  interp_files,interpretations,$w,$s,$z,$1,$2))))
interp_params = $(common_params) param;interp_width=$(INTERP_WIDTH) param;interp_height=$(INTERP_HEIGHT) \
  param;interp_best=$(INTERP_BEST) param;interpretation=$(interp_default)
interpretations-grid_figures := best.txt
interpretations_figures := interpretations.png interpretations-cells.csv
INTERP_FINAL ?=
ifneq ($(call wanted,interpretations)$(call wanted,interpretations-grid),)
interpretations-grid_lines := $(interp_params) $(call interp_rows,$(INTERP_WIDTH),$(INTERP_HEIGHT),$(interp_grid),grid,$(INTERP_SCENES))
$(eval $(call study_rule,interpretations-grid))
ifneq ($(INTERP_FINAL),)
interpretations_lines := $(interp_params) param;interp_final_width=$(INTERP_FINAL_WIDTH) \
  param;interp_final_height=$(INTERP_FINAL_HEIGHT) param;grid_csv=$(OUT)/interpretations-grid/interpretations-grid.csv \
  $(call interp_rows,$(INTERP_FINAL_WIDTH),$(INTERP_FINAL_HEIGHT),$(sort $(INTERP_FINAL) $(interp_default)),final,$(INTERP_FINAL_SCENES))
$(eval $(call study_rule,interpretations))
# Its report reads the grid's CSV too (what each axis does).
$(OUT)/interpretations/interpretations.md: $(OUT)/interpretations-grid/interpretations-grid.csv
else
# Under `all`, after the others but calibration: its final traces may be theirs.
interpretations: interpretations-grid $(if $(filter all,$(goals)),$(filter-out interpretations \
  calibration,$(ALL_TARGETS)))
	@$(call second_phase_dry_run,interpretations,$(OUT)/interpretations-grid/best.txt)best="$$(cat \
	  $(OUT)/interpretations-grid/best.txt)"; \
	  if [ -z "$$best" ]; then echo "interpretations: $(OUT)/interpretations-grid/best.txt is empty (INTERP_BEST=$(INTERP_BEST))" >&2; exit 1; fi; \
	  $(MAKE) --no-print-directory -f $(MK_FILE) interpretations INTERP_FINAL="$$best"
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
  scene_hash,$1) $(call samp_render,$1,$2) $(call samp_sim,$2)).csv,--render '$(call samp_render,$1,$2) \
  $(tree_cache_option)' \
  --keep-trace --simulate '$(call samp_sim,$2)',,full $1 $2)
# $(call samp_run,SCENE,SIZE,METHOD,RATE,SEED): one sampled run's CSV.
samp_run = $(if $(filter rows,$3),$(call define_samp,$(samp_runs)/rows-$(call hash_text,$(tracer_hash) \
  $(cachesim_hash) $(call scene_hash,$1) $(call samp_render,$1,$2) $(call samp_method_render,$3,$4,$5) \
  $(call samp_sim,$2)).csv,--render '$(call samp_render,$1,$2) $(call samp_method_render,$3,$4,$5) \
  $(tree_cache_option)' \
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

# --- inflight: the split's gain and the L2 against rays in flight and units --
# One trace per scene, rays in flight and units, in the hybrid layout sized
# for the high cache of the largest size (its BFL part holds the top levels
# of every smaller one too: K = auto per size); each size per unit.
inflight_figures := inflight.png
ifneq ($(call wanted,inflight),)
inflight_largest := $(shell printf '%s\n' $(foreach z,$(SIZES),$(call size_bytes,$z)) | sort -n | tail -n 1)
inflight_render = $(call render_options,$(INFLIGHT_WIDTH),$(INFLIGHT_HEIGHT),$(FRAME),$(kd_default)) --layout hybrid \
  --high-size $(shell echo $$(( $(inflight_largest) / 2 ))) --pixel-order tiled --rays-in-flight $1 --units $2
inflight_sim = --units private --size $(call join_commas,$(SIZES)) --block $(BLOCK) --assoc 1 --scheme \
  single$(comma)split --split-level auto --l2-size $(INFLIGHT_L2_SIZE) --l2-block $(INFLIGHT_L2_BLOCK) \
  --l2-assoc $(INFLIGHT_L2_ASSOC)
inflight_lines := $(common_params) param;inflight_width=$(INFLIGHT_WIDTH) param;inflight_height=$(INFLIGHT_HEIGHT) \
  param;l2_size=$(INFLIGHT_L2_SIZE) param;l2_block=$(INFLIGHT_L2_BLOCK) param;l2_assoc=$(INFLIGHT_L2_ASSOC) \
  $(foreach s,$(INFLIGHT_SCENES),$(foreach u,$(INFLIGHT_UNITS),$(foreach n,$(INFLIGHT_RAYS),row;scene=$s;units=$u;rays=$n;file=$(call \
  sim,inflight,$(call trace,$s,$(call inflight_render,$n,$u)),$(inflight_sim)))))
$(eval $(call study_rule,inflight))
endif

# --- policies: hardware replacement policies and the optimum beside the split --
# One trace per scene, structure and size (hybrid layout sized for that
# size's high cache, K = auto); per block size one run of the single cache
# under every policy and one of the split (high cache retained) with each
# low-cache policy: the opt configurations of a run share their kept fetches.
policies_figures := policies.png
ifneq ($(call wanted,policies),)
pol_render = $(call render_options,$(POLICY_WIDTH),$(POLICY_HEIGHT),$(FRAME),$(kd_default))$(if $(filter \
  kdtree,$1),, --accel $1) $(call hybrid_for,$2)
pol_sim = $(call sim,policies,$(call trace,$1,$(call pol_render,$2,$3)),--size $3 --block $4 --assoc $(call \
  join_commas,$(POLICY_ASSOCS)) $5)
policies_lines := $(common_params) param;policy_width=$(POLICY_WIDTH) param;policy_height=$(POLICY_HEIGHT) \
  $(foreach s,$(POLICY_SCENES),$(foreach a,$(POLICY_ACCELS),$(foreach z,$(POLICY_SIZES),$(foreach \
  b,$(POLICY_BLOCKS),row;scene=$s;accel=$a;size=$z;block=$b;single=$(call pol_sim,$s,$a,$z,$b,--policy $(call \
  join_commas,$(POLICY_SINGLE)) --scheme single);split=$(call pol_sim,$s,$a,$z,$b,--policy $(call \
  join_commas,$(POLICY_SPLIT)) --scheme split --split-level auto)))))
$(eval $(call study_rule,policies))
endif

# --- prefetch: treelet prefetching and Dinero IV's tagged prefetch beside the split --
# One trace per scene, structure, integrator and treelet size, in the
# treelet layout (the only one whose trace carries treelet maps); on it one
# run of single and split without and with the treelet prefetcher, and one
# of the single cache under --fetch tagged (Dinero IV's fetch policies are
# the single scheme's only).
prefetch_figures := prefetch.png
ifneq ($(call wanted,prefetch),)
prefetch_integrator = $(if $(filter whitted,$1),--max-depth $(DEPTH),$(if $(filter path,$1),--integrator path --spp \
  $(PREFETCH_SPP),$(error PREFETCH_INTEGRATORS: '$1' is neither whitted nor path)))
prefetch_render = --width $(PREFETCH_WIDTH) --height $(PREFETCH_HEIGHT) --frame $(FRAME) $(kd_default) $(call \
  prefetch_integrator,$1)$(if $(filter kdtree,$2),, --accel $2) --treelet-bytes $3 --layout treelet
prefetch_grid = --size $(call join_commas,$(SIZES)) --block $(PREFETCH_BLOCK) --assoc $(call join_commas,$(PREFETCH_ASSOCS))
prefetch_trace = $(call trace,$1,$(call prefetch_render,$2,$3,$4))
prefetch_lines := $(common_params) param;prefetch_width=$(PREFETCH_WIDTH) param;prefetch_height=$(PREFETCH_HEIGHT) \
  param;prefetch_block=$(PREFETCH_BLOCK) param;prefetch_spp=$(PREFETCH_SPP) \
  $(foreach s,$(PREFETCH_SCENES),$(foreach a,$(PREFETCH_ACCELS),$(foreach i,$(PREFETCH_INTEGRATORS),$(foreach \
  t,$(PREFETCH_TREELET_BYTES),row;scene=$s;accel=$a;integrator=$i;treelet_bytes=$t;trace=$(call \
  prefetch_trace,$s,$i,$a,$t);treelet=$(call sim,prefetch,$(call prefetch_trace,$s,$i,$a,$t),$(prefetch_grid) \
  --scheme single$(comma)split --split-level auto --prefetch none$(comma)treelet);tagged=$(call sim,prefetch,$(call \
  prefetch_trace,$s,$i,$a,$t),$(prefetch_grid) --scheme single --fetch tagged)))))
$(eval $(call study_rule,prefetch))
endif

# The path-tracing studies (workloads, convergence).
include $(MK_DIR)/path-tracing.mk

# The renders this make runs (progress: which of them this one is): the
# leaders of the groups with a trace missing, one render each. After every
# study's file is included, path-tracing.mk's too: its groups count.
to_render := $(foreach g,$(all_groups),$(if $(filter-out $(wildcard $(group_files_$g)),$(group_files_$g)),$(group_leader_$g)))

clean:
	rm -rf $(OUT)/traces $(addprefix $(OUT)/,$(ALL_TARGETS) calibration-grid interpretations-grid)
