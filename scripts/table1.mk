# Table 1 of Nah et al., "A Split Node Cache Scheme for Fast Ray Tracing":
# miss ratios of 4, 8 and 16 KB direct-mapped node caches with 8-byte blocks,
# without (single) and with (split) the split scheme, 800x600, ray depth 10,
# laid out as the paper's table beside the paper's numbers.
#
#   make -f scripts/table1.mk                  # Robot, Kitchen, forest: out/table1/
#   make -f scripts/table1.mk SCENES=robot     # one scene
#   make -f scripts/table1.mk WIDTH=200 HEIGHT=150 OUT=out/small   # a quick look
#
# It is the table1 target of scripts/experiments.mk (the other studies, the
# parameters and how rebuilds are decided are described there).
.DEFAULT_GOAL := table1
include $(dir $(lastword $(MAKEFILE_LIST)))experiments.mk
