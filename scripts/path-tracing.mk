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
# CONV_SCENES at CONV_WIDTH x CONV_HEIGHT rendered at each of CONV_SPP
# samples per pixel (doubling from 1) and once at CONV_REFERENCE_SPP, the
# reference; RMSE and relative MSE over every pixel and channel of the PFM
# images against the reference, beside the CPU time (user + sys) of each
# whole `tracer render` (no trace written), and the slope of log RMSE
# against log spp beside the expected -0.5. Each render builds its own tree
# (no tree cache), so every CPU time includes the build, not only the first
# of each scene's. The reference must be above every CONV_SPP: a run shares
# its samples with the reference's first ones (the same random numbers), so
# a reference of no more samples is one of the runs (RMSE 0).
CONV_SCENES ?= robot kitchen
CONV_WIDTH ?= 64
CONV_HEIGHT ?= 48
CONV_SPP ?= 1 2 4 8 16 32 64
CONV_REFERENCE_SPP ?= 1024

convergence_figures := convergence.png
ifneq ($(call wanted,convergence),)
conv_not_below := $(shell for n in $(CONV_SPP); do [ "$$n" -lt "$(CONV_REFERENCE_SPP)" ] 2>/dev/null || echo "$$n"; done)
$(if $(conv_not_below),$(error CONV_REFERENCE_SPP=$(CONV_REFERENCE_SPP) is not above CONV_SPP $(conv_not_below): \
  the reference must have more samples per pixel than every measured render, whose samples are its first ones))
conv_runs := $(OUT)/convergence/runs
conv_render = $(call scene_arg,$1) -q --width $(CONV_WIDTH) --height $(CONV_HEIGHT) --frame $(FRAME) $(kd_default) \
  --integrator path --spp $2
# $(call conv_image,SCENE,SPP): the render's timing (CSV: wall,user,sys); its image beside it (.pfm).
conv_image = $(call define_conv,$(conv_runs)/$(call hash_text,$(tracer_hash) $(call scene_hash,$1) $(call \
  conv_render,$1,$2)).csv,$(call conv_render,$1,$2),$1 $2 spp)
define_conv = $(if $(defined_$1),,$(eval $(call conv_rule,$1,$2,$3))$(eval defined_$1 := 1))$1
define conv_rule
$1: | $(conv_runs)/.dir
	@echo "convergence: render $3" >&2
	@$(RUN) /usr/bin/time -f 'wall,user,sys\n%e,%U,%S' -o $$@.tmp$$$$$$$$ $(TRACER) render $2 --tree-cache '' --pfm $(1:.csv=.pfm) \
	  && mv $$@.tmp$$$$$$$$ $$@ || { rm -f $$@.tmp$$$$$$$$; exit 1; }
endef
convergence_lines := $(common_params) param;conv_width=$(CONV_WIDTH) param;conv_height=$(CONV_HEIGHT) \
  param;reference_spp=$(CONV_REFERENCE_SPP) \
  $(foreach s,$(CONV_SCENES),row;scene=$s;spp=$(CONV_REFERENCE_SPP);reference=yes;file=$(call \
  conv_image,$s,$(CONV_REFERENCE_SPP)) $(foreach n,$(CONV_SPP),row;scene=$s;spp=$n;reference=no;file=$(call \
  conv_image,$s,$n)))
$(eval $(call study_rule,convergence))
endif
