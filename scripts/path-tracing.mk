# Path-tracing studies (workloads, convergence), included by experiments.mk
# (its helpers, variables and study_rule; docs/guide/path-tracing.md).
#
# --- workloads: Table 1's grid for the Whitted and the path tracer ----------
# workloads: Table 1's grid (SIZES, direct-mapped and WORKLOADS_ASSOCS-way,
# single against split with K = auto, each size's trace in the hybrid
# layout sized for its high cache) for the Whitted tracer against the path
# tracer at each of WORKLOADS_SPP samples per pixel, for each structure of
# WORKLOADS_ACCELS, at each of WORKLOADS_RAYS rays in flight (one unit),
# on WORKLOADS_SCENES at WORKLOADS_WIDTH x WORKLOADS_HEIGHT. Path traces use
# the tracer's default bounces (5, Russian roulette from the third).
WORKLOADS_SCENES ?= robot kitchen
WORKLOADS_WIDTH ?= 100
WORKLOADS_HEIGHT ?= 75
WORKLOADS_SPP ?= 1 4
WORKLOADS_ACCELS ?= kdtree bvh2 cwbvh8
WORKLOADS_RAYS ?= 1 32
WORKLOADS_ASSOCS ?= 1 4

workloads_figures := workloads.png
ifneq ($(call wanted,workloads),)
# Integrators as words: whitted, or path-N for N samples per pixel.
workloads_integrators := whitted $(addprefix path-,$(WORKLOADS_SPP))
workloads_integrator_options = $(if $(filter whitted,$1),--max-depth $(DEPTH),--integrator path --spp $(patsubst path-%,%,$1))
workloads_render = --width $(WORKLOADS_WIDTH) --height $(WORKLOADS_HEIGHT) --frame $(FRAME) $(kd_default) $(call \
  workloads_integrator_options,$1)$(if $(filter kdtree,$2),, --accel $2)$(if $(filter 1,$3),, --rays-in-flight $3)
workloads_sim = --size $1 --block $(BLOCK) --assoc $(call join_commas,$(WORKLOADS_ASSOCS)) --scheme \
  single$(comma)split --split-level auto
workloads_lines := $(common_params) param;workloads_width=$(WORKLOADS_WIDTH) \
  param;workloads_height=$(WORKLOADS_HEIGHT) \
  $(foreach s,$(WORKLOADS_SCENES),$(foreach i,$(workloads_integrators),$(foreach a,$(WORKLOADS_ACCELS),$(foreach \
  n,$(WORKLOADS_RAYS),$(foreach z,$(SIZES),row;scene=$s;integrator=$i;accel=$a;rays=$n;size=$z;trace=$(call \
  trace,$s,$(call workloads_render,$i,$a,$n) $(call hybrid_for,$z));file=$(call sim,workloads,$(call \
  trace,$s,$(call workloads_render,$i,$a,$n) $(call hybrid_for,$z)),$(call workloads_sim,$z)))))))
$(eval $(call study_rule,workloads))
endif

# --- convergence: the path-traced image's error against CPU time ------------
# convergence: the path-traced image's error against CPU time. Each scene of
# CONV_SCENES at CONV_WIDTH x CONV_HEIGHT rendered with each sampler of
# CONV_SAMPLERS at each of CONV_SPP samples per pixel (doubling from 1) on
# one thread, and once at CONV_REFERENCE_SPP, the reference; RMSE and
# relative MSE over every pixel and channel of the PFM images against the
# reference, beside the CPU time (user + sys) of each whole `tracer render`
# (no trace written), and the slope of log RMSE against log spp beside the
# expected -0.5. Each render builds its own tree (no tree cache), so every
# CPU time includes the build, not only the first of each scene's. The
# reference must be above every CONV_SPP: a run shares its samples with the
# reference's first ones (the same random numbers), so a reference of no
# more samples is one of the runs (RMSE 0). A scene of scripts/cycles/scenes.py
# (cornell) is rendered by Blender Cycles (CONV_BLENDER) too, on one thread,
# seed 1, at each CONV_SPP, with the bounces that match ours (5), its CPU
# time the process's during the render (Blender's start-up left out); its
# reference is Cycles' at CONV_CYCLES_REFERENCE_SPP, seed 1000, independent
# of every run, ours and Cycles'.
CONV_SCENES ?= robot kitchen cornell
CONV_SAMPLERS ?= independent sobol
CONV_WIDTH ?= 64
CONV_HEIGHT ?= 48
CONV_SPP ?= 1 2 4 8 16 32 64
CONV_REFERENCE_SPP ?= 1024
CONV_CYCLES_REFERENCE_SPP ?= 16384
CONV_BLENDER ?= blender
# The tracer's default bounces, which the renders keep.
conv_bounces := 5

convergence_figures := convergence.png
ifneq ($(call wanted,convergence),)
conv_not_below := $(shell for n in $(CONV_SPP); do [ "$$n" -lt "$(CONV_REFERENCE_SPP)" ] 2>/dev/null || echo "$$n"; done)
$(if $(conv_not_below),$(error CONV_REFERENCE_SPP=$(CONV_REFERENCE_SPP) is not above CONV_SPP $(conv_not_below): \
  the reference must have more samples per pixel than every measured render, whose samples are its first ones))
conv_runs := $(OUT)/convergence/runs
conv_render = $(call scene_arg,$1) -q --width $(CONV_WIDTH) --height $(CONV_HEIGHT) --frame $(FRAME) $(kd_default) \
  --integrator path --spp $2 --sampler $3 --threads 1
# $(call conv_image,SCENE,SPP,SAMPLER): the render's timing (CSV: wall,user,sys); its image beside it (.pfm).
conv_image = $(call define_conv,$(conv_runs)/$(call hash_text,$(tracer_hash) $(call scene_hash,$1) $(call \
  conv_render,$1,$2,$3)).csv,$(call conv_render,$1,$2,$3),$1 $2 spp $3)
define_conv = $(if $(defined_$1),,$(eval $(call conv_rule,$1,$2,$3))$(eval defined_$1 := 1))$1
define conv_rule
$1: | $(conv_runs)/.dir $(filter $(OUT)/scenes/%,$(firstword $2))
	@echo "convergence: render $3" >&2
	@$(RUN) /usr/bin/time -f 'wall,user,sys\n%e,%U,%S' -o $$@.tmp$$$$$$$$ $(TRACER) render $2 --tree-cache '' --pfm $(1:.csv=.pfm) \
	  && mv $$@.tmp$$$$$$$$ $$@ || { rm -f $$@.tmp$$$$$$$$; exit 1; }
endef
# $(call conv_cycles,SCENE,SPP,SEED,THREADS): Cycles' timing (the same CSV)
# and its image beside it (.pfm); Blender's output in a .log beside them.
conv_cycles_args = $1 --spp $2 --seeds $3 --our-bounces $(conv_bounces) --threads $4 --width $(CONV_WIDTH) \
  --height $(CONV_HEIGHT)
conv_blender_version = $(or $(conv_blender_value),$(eval conv_blender_value := $(or $(shell $(CONV_BLENDER) --version \
  2>/dev/null | head -1),$(error $(CONV_BLENDER) does not run: install Debian's blender \
  (scripts/install-packages.sh blender))))$(conv_blender_value))
conv_cycles = $(call define_conv_cycles,$(conv_runs)/cycles-$(call hash_text,$(conv_blender_version) $(call \
  file_hash,$(MK_DIR)/cycles/render_cycles.py) $(call scene_hash,$1) $(call conv_cycles_args,$1,$2,$3,$4)).csv,$(call \
  conv_cycles_args,$1,$2,$3,$4),$3,$1 $2 spp Cycles)
define_conv_cycles = $(if $(defined_$1),,$(eval $(call conv_cycles_rule,$1,$2,$3,$4))$(eval defined_$1 := 1))$1
define conv_cycles_rule
$1: | $(conv_runs)/.dir
	@echo "convergence: render $4" >&2
	@$(RUN) $(CONV_BLENDER) -b --factory-startup --python $(MK_DIR)/cycles/render_cycles.py -- $(firstword $2) $(1:.csv=) \
	  $(wordlist 2,99,$2) \
	  >$(1:.csv=.log) 2>&1 || { tail -20 $(1:.csv=.log) >&2; exit 1; }
	@mv $(1:.csv=)-seed$3.pfm $(1:.csv=.pfm)
	@tail -n 1 $(1:.csv=)-times.csv | awk -F, '{print "wall,user,sys"; print $$$$2 "," $$$$3 ",0"}' >$$@.tmp \
	  && mv $$@.tmp $$@
endef
conv_scene_rows = $(if $(filter $(CYCLES_SCENES),$1),row;scene=$1;sampler=cycles;spp=$(CONV_CYCLES_REFERENCE_SPP);reference=yes;file=$(call \
  conv_cycles,$1,$(CONV_CYCLES_REFERENCE_SPP),1000,2) $(foreach n,$(CONV_SPP),row;scene=$1;sampler=cycles;spp=$n;reference=no;file=$(call \
  conv_cycles,$1,$n,1,1)),row;scene=$1;sampler=independent;spp=$(CONV_REFERENCE_SPP);reference=yes;file=$(call \
  conv_image,$1,$(CONV_REFERENCE_SPP),independent)) $(foreach p,$(CONV_SAMPLERS),$(foreach \
  n,$(CONV_SPP),row;scene=$1;sampler=$p;spp=$n;reference=no;file=$(call conv_image,$1,$n,$p)))
convergence_lines := $(common_params) param;conv_width=$(CONV_WIDTH) param;conv_height=$(CONV_HEIGHT) \
  param;reference_spp=$(CONV_REFERENCE_SPP) param;cycles_reference_spp=$(CONV_CYCLES_REFERENCE_SPP) \
  $(foreach s,$(CONV_SCENES),$(call conv_scene_rows,$s))
$(eval $(call study_rule,convergence))
endif
