"""A reading of the paper's open choices: one word of twelve fields, as
scripts/experiments.mk writes it, its cells against the paper's Table 1, and
how close it comes (mean and largest difference, directions of the split)."""

import common

AXES = ["size", "base", "loads", "k", "depth", "tcost", "icost", "bonus", "leaf", "rays", "lights", "frame"]
# What each axis's values mean (docs/guide/studies.md "Reproducing Table 1",
# docs/REPRODUCTION.md).
AXIS_TEXT = {
    "size": "what a row's size is: half (the total, split half and half), each (each cache the row's "
            "size), highk (the high cache holds the levels < K, the low cache the row's size)",
    "base": "the layout of the 'without' column: hybrid (the split's own trace), dfl, bfl, veb",
    "loads": "the high cache's loads: free (not misses) or counted as misses",
    "k": "K, the levels in the high cache: auto (the most that fit it) or fixed",
    "depth": "kd-tree depth limit (default: 8 + 1.3 log2 N)",
    "tcost": "SAH traversal cost", "icost": "SAH intersection cost", "bonus": "SAH empty bonus",
    "leaf": "leaf-size rule: a node of at most this many triangles is a leaf (0: the SAH alone)",
    "rays": "rays traced: whitted, primary+shadow, primary",
    "lights": "lights with shadow rays: all, or the first only",
    "frame": "animation frame",
}
BART = ("robot", "kitchen")


def parse(word):
    fields = word.split(":")
    if len(fields) != len(AXES):
        raise SystemExit(f"interpretation '{word}': expected {len(AXES)} fields separated by ':'")
    return dict(zip(AXES, fields))


def make_argument(word):
    """The make variable that selects this reading."""
    return "INTERPRETATION=" + ",".join(f"{a}={v}" for a, v in parse(word).items())


def describe(word):
    a = parse(word)
    depth = "8+1.3 log2 N" if a["depth"] == "default" else a["depth"]
    return (f"size {a['size']}, base {a['base']}, loads {a['loads']}, K {a['k']}; tree depth {depth}, "
            f"costs {a['tcost']}/{a['icost']}, bonus {a['bonus']}, leaf {a['leaf']}; rays {a['rays']}, "
            f"lights {a['lights']}, frame {a['frame']}")


def cells(rows, paper):
    """One record per manifest row: ours and the paper's without / with."""
    out = []
    for row in rows:
        single_rows, _ = common.read_cachesim(row["single"])
        split_rows, _ = common.read_cachesim(row["split"])
        single = common.pick(single_rows, scheme="single", size=common.size_bytes(row["size"]))
        split = common.pick(split_rows, scheme="split")
        ours_without, ours_with = common.percent(single), common.percent(split)
        known = paper.get((row["scene"], row["size"]), {})
        p_without, p_with = known.get("without"), known.get("with")
        ours_better = common.better_of(ours_without, ours_with)
        record = {"phase": row.get("phase", ""), "interp": row["interp"]}
        record.update(parse(row["interp"]))
        record.update({
            "scene": row["scene"], "stand_in": "yes" if row["scene"] not in BART else "no",
            "size_row": row["size"], "single_size": single["size"], "high_size": split["high_size"],
            "low_size": split["low_size"], "split_level": split["split_level"],
            "without_ours": f"{ours_without:.4f}", "without_paper": common.fmt(p_without),
            "without_diff": None if p_without is None else f"{ours_without - p_without:+.4f}",
            "with_ours": f"{ours_with:.4f}", "with_paper": common.fmt(p_with),
            "with_diff": None if p_with is None else f"{ours_with - p_with:+.4f}",
            "our_better": ours_better, "paper_better": known.get("better"),
            "direction_agrees": None if known.get("better") is None else
            ("yes" if known["better"] == ours_better else "no"),
            "fetches": single["fetches"], "single_misses": single["misses"], "split_misses": split["misses"],
            "high_loads": split["high_loads"],
        })
        out.append(record)
    return out


def _measures(mine):
    diffs = [abs(float(r[c])) for r in mine for c in ("without_diff", "with_diff") if r[c] is not None]
    known = [r for r in mine if r["direction_agrees"] is not None]
    return (sum(diffs) / len(diffs) if diffs else None, max(diffs) if diffs else None,
            sum(r["direction_agrees"] == "yes" for r in known), len(known), len(diffs))


def score(records):
    """Per reading: over the BART cells (the goal) and over all cells (the
    forest standing in for Fairy Forest): mean and largest |ours - paper|,
    directions agreeing; the mean miss ratios. Closest first."""
    by_word = {}
    for r in records:
        by_word.setdefault(r["interp"], []).append(r)
    summary = []
    for word, mine in by_word.items():
        bart = [r for r in mine if r["stand_in"] == "no"]
        mad, largest, agree, known, count = _measures(bart)
        mad_all, largest_all, agree_all, known_all, count_all = _measures(mine)
        entry = {"interp": word}
        entry.update(parse(word))
        entry.update({
            "bart_cells": count, "bart_mean_abs_diff": common.fmt(mad, 4), "bart_max_abs_diff": common.fmt(largest, 4),
            "bart_directions_agree": agree, "bart_directions_known": known,
            "all_cells": count_all, "all_mean_abs_diff": common.fmt(mad_all, 4),
            "all_max_abs_diff": common.fmt(largest_all, 4), "all_directions_agree": agree_all,
            "all_directions_known": known_all,
            "bart_mean_without": f"{sum(float(r['without_ours']) for r in bart) / max(1, len(bart)):.4f}",
            "bart_mean_with": f"{sum(float(r['with_ours']) for r in bart) / max(1, len(bart)):.4f}",
            "meets_goal": "yes" if mad is not None and mad <= 1.0 and largest <= 2.0 and agree == known == 6 else "no",
            "_mad": mad, "_max": largest, "_agree": agree, "_cells": mine})
        summary.append(entry)
    summary.sort(key=lambda s: (s["_mad"] is None, s["_mad"] or 0, s["_max"] or 0, -s["_agree"], s["interp"]))
    return summary


def same_numbers(entry):
    """What two readings with the same miss ratios in every cell share (e.g.
    'each' and 'highk' at a fixed K: the retained high levels never miss)."""
    return tuple((r["scene"], r["size_row"], r["without_ours"], r["with_ours"]) for r in entry["_cells"])


def distinct(summary):
    """The readings in rank order, each with the better-ranked reading whose
    numbers it repeats (None when its numbers are its own)."""
    seen = {}
    out = []
    for s in summary:
        key = same_numbers(s)
        out.append((s, seen.get(key)))
        seen.setdefault(key, s["interp"])
    return out


def public(entry):
    return {k: v for k, v in entry.items() if not k.startswith("_")}


def ranking_table(summary, default_word, limit=None, with_all=False, same=None):
    header = ["rank", "reading", "BART mean abs diff", "BART max abs diff", "BART directions"]
    if with_all:
        header += ["all 18 mean abs diff (forest stands in)", "all directions"]
    body = []
    for i, s in enumerate(summary[:limit] if limit else summary, 1):
        name = describe(s["interp"]) + (" **(default)**" if s["interp"] == default_word else "")
        if same and same.get(s["interp"]):
            name += f" (the same numbers as rank {[e['interp'] for e in summary].index(same[s['interp']]) + 1})"
        line = [i, name, s["bart_mean_abs_diff"], s["bart_max_abs_diff"],
                f"{s['bart_directions_agree']} / {s['bart_directions_known']}"]
        if with_all:
            line += [s["all_mean_abs_diff"], f"{s['all_directions_agree']} / {s['all_directions_known']}"]
        body.append(line)
    return common.markdown_table(header, body)


def table1_layout(entry):
    """The cells of one reading as the paper lays Table 1 out: ours / paper (diff)."""
    cells_of = {(r["scene"], r["size_row"]): r for r in entry["_cells"]}
    scenes = list(dict.fromkeys(r["scene"] for r in entry["_cells"]))
    sizes = list(dict.fromkeys(r["size_row"] for r in entry["_cells"]))
    header = ["Size"]
    for s in scenes:
        name = common.paper_name(s)
        header += [f"{name} without", f"{name} with", f"{name}: split"]
    body = []
    for z in sizes:
        line = [common.size_label(common.size_bytes(z))]
        for s in scenes:
            c = cells_of[(s, z)]
            for column in ("without", "with"):
                ours = float(c[f"{column}_ours"])
                line.append(f"{ours:.2f}" if not c[f"{column}_paper"] else
                            f"{ours:.2f} / {c[f'{column}_paper']} ({float(c[f'{column}_diff']):+.2f})")
            word = {"split": "helps", "single": "hurts", "tie": "no change"}
            theirs = word.get(c["paper_better"], "?")
            line.append(f"{word[c['our_better']]} / {theirs}" +
                        ("" if c["direction_agrees"] is None else
                         (" (agrees)" if c["direction_agrees"] == "yes" else " (DISAGREES)")))
        body.append(line)
    return common.markdown_table(header, body)


def axis_effects(summary, centre_word):
    """Each axis's values with the others as in `centre_word`: how close each
    comes and what it does to the mean miss ratios (BART cells)."""
    by_word = {s["interp"]: s for s in summary}
    centre = parse(centre_word)
    body = []
    for axis in AXES:
        values = sorted({parse(w)[axis] for w in by_word})
        if len(values) < 2:
            continue
        for value in values:
            word = ":".join(value if a == axis else centre[a] for a in AXES)
            s = by_word.get(word)
            if s is None:
                continue
            body.append([axis, value + (" (centre)" if value == centre[axis] else ""), s["bart_mean_abs_diff"],
                         s["bart_max_abs_diff"], f"{s['bart_directions_agree']} / {s['bart_directions_known']}",
                         s["bart_mean_without"], s["bart_mean_with"],
                         f"{float(s['bart_mean_without']) - float(s['bart_mean_with']):+.2f}"])
    return common.markdown_table(["axis", "value", "BART mean abs diff", "max abs diff", "directions",
                                  "mean without (%)", "mean with (%)", "mean gain (points)"], body)
