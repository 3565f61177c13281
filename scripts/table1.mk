# Table 1 of Nah et al., "A Split Node Cache Scheme for Fast Ray Tracing":
# miss ratios of 4, 8 and 16 KB direct-mapped node caches with 8-byte blocks,
# without (single) and with (split) the split scheme, 800x600, ray depth 10.
#
#   make -f scripts/table1.mk                  # all scenes, table on stdout
#   make -f scripts/table1.mk SCENES=robot     # one scene
#   make -f scripts/table1.mk WIDTH=200 HEIGHT=150 OUT=out/small   # a quick look
#
# Each (scene, size) pair gets its own trace: the hybrid layout's BFL block is
# sized for that row's high-level cache (half the total), as in the paper.
# The Fairy Forest scene is not available; the built-in `forest` stands in.

BUILD ?= build
SHARED ?= ../shared
OUT ?= out/table1
WIDTH ?= 800
HEIGHT ?= 600
DEPTH ?= 10
SCENES ?= robot kitchen forest
SIZES ?= 4k 8k 16k

TRACER := $(BUILD)/bin/tracer
CACHESIM := $(BUILD)/bin/cachesim

scene_robot := $(SHARED)/scenes/bart/robots/Robot.aff
scene_kitchen := $(SHARED)/scenes/bart/kitchen/kitchen.aff
scene_forest := forest

half_4k := 2k
half_8k := 4k
half_16k := 8k

ROWS := $(foreach s,$(SCENES),$(foreach z,$(SIZES),$(OUT)/$(s)-$(z).csv))

.PHONY: table clean
.DELETE_ON_ERROR:
.SECONDARY:

table: $(OUT)/table1.csv
	@column -s, -t < $<

$(OUT)/table1.csv: $(ROWS)
	@head -n 1 $< > $@.tmp
	@for f in $^; do tail -n +2 $$f; done >> $@.tmp
	@mv $@.tmp $@

# Scene and size come from the file name: OUT/SCENE-SIZE.din.zst.
$(OUT)/%.din.zst:
	@mkdir -p $(OUT)
	$(TRACER) render $(scene_$(firstword $(subst -, ,$*))) -q \
	  --width $(WIDTH) --height $(HEIGHT) --max-depth $(DEPTH) \
	  --layout hybrid --high-size $(half_$(lastword $(subst -, ,$*))) -o $@

$(OUT)/%.csv: $(OUT)/%.din.zst
	$(CACHESIM) run $< --size $(lastword $(subst -, ,$*)) --block 8 --assoc 1 \
	  --scheme single,split --split-level auto --format csv > $@.tmp
	@mv $@.tmp $@

clean:
	rm -rf $(OUT)
