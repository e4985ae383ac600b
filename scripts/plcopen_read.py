"""Second, independent reader of the PLCopen documents `higraph-lsp build --target plcopen`
writes: the `plcopen` PyPI package (xsdata bindings generated from tc6_xml_v201.xsd) parses
each file strictly (unknown elements or attributes and unconvertible values fail), then the
SFC bodies are checked as an importer needs them: localIds unique, every connection names an
element of the same POU, an initial step, jump targets that are steps, step names unique,
every transition with an ST condition, every named action with an ST body, every action
association naming a variable or an action of its POU. Usage: python plcopen_read.py FILE... (exit 1 on the
first problem of any file)."""

import sys

import plcopen
from xsdata.formats.dataclass.context import XmlContext
from xsdata.formats.dataclass.parsers import XmlParser
from xsdata.formats.dataclass.parsers.config import ParserConfig

SFC_LISTS = [
    "step",
    "transition",
    "jump_step",
    "selection_divergence",
    "selection_convergence",
    "simultaneous_divergence",
    "simultaneous_convergence",
    "action_block",
]


def inputs(element):
    """The connectionPointIn elements of an SFC element (one or a list)."""
    cpi = getattr(element, "connection_point_in", None)
    if cpi is None:
        return []
    return cpi if isinstance(cpi, list) else [cpi]


def check(path, parser):
    with open(path, "rb") as f:
        project = parser.from_bytes(f.read(), plcopen.Project)
    problems = []
    seen_ids = set()
    counts = {"pous": 0, "steps": 0, "transitions": 0}
    for pou in project.types.pous.pou:
        counts["pous"] += 1
        if str(pou.pou_type.value) != "functionBlock":
            problems.append(f"POU {pou.name}: pouType {pou.pou_type.value}")
        sfcs = [b.sfc for b in pou.body if b.sfc is not None]
        if len(sfcs) != 1:
            problems.append(f"POU {pou.name}: {len(sfcs)} SFC bodies")
            continue
        sfc = sfcs[0]
        ids = set()
        for name in SFC_LISTS:
            for element in getattr(sfc, name):
                for lid in [element.local_id] + [a.local_id for a in getattr(element, "action", [])]:
                    if lid in seen_ids:
                        problems.append(f"POU {pou.name}: localId {lid} twice")
                    seen_ids.add(lid)
                    ids.add(lid)
        for name in SFC_LISTS:
            for element in getattr(sfc, name):
                for cpi in inputs(element):
                    for c in cpi.connection:
                        if c.ref_local_id not in ids:
                            problems.append(
                                f"POU {pou.name}: {name} {element.local_id} connects to "
                                f"missing {c.ref_local_id}"
                            )
        steps = [s.name for s in sfc.step]
        if len(set(steps)) != len(steps):
            problems.append(f"POU {pou.name}: step names not unique")
        if not any(s.initial_step for s in sfc.step):
            problems.append(f"POU {pou.name}: no initial step")
        for j in sfc.jump_step:
            if j.target_name not in steps:
                problems.append(f"POU {pou.name}: jump to unknown step {j.target_name}")
        for t in sfc.transition:
            inline = t.condition.inline if t.condition else None
            text = inline.st.w3_org_1999_xhtml_element.text if inline and inline.st else None
            if not text:
                problems.append(f"POU {pou.name}: transition {t.local_id} without ST condition")
        actions = set()
        for a in pou.actions.action if pou.actions else []:
            actions.add(a.name)
            sts = [b.st for b in (a.body if isinstance(a.body, list) else [a.body]) if b.st]
            if not sts or not sts[0].w3_org_1999_xhtml_element.text:
                problems.append(f"POU {pou.name}: action {a.name} without an ST body")
        variables = set()
        for kind in ["input_vars", "output_vars", "in_out_vars", "local_vars", "external_vars"]:
            for var_list in getattr(pou.interface, kind, []) or []:
                variables.update(v.name for v in var_list.variable)
        for block in sfc.action_block:
            for a in block.action:
                if a.reference is not None and a.reference.name not in actions | variables:
                    problems.append(
                        f"POU {pou.name}: action {a.local_id} names {a.reference.name}, "
                        "neither a variable nor an action"
                    )
        counts["steps"] += len(steps)
        counts["transitions"] += len(sfc.transition)
    return problems, counts


def main():
    parser = XmlParser(
        context=XmlContext(),
        config=ParserConfig(
            fail_on_unknown_properties=True,
            fail_on_unknown_attributes=True,
            fail_on_converter_warnings=True,
        ),
    )
    failed = False
    for path in sys.argv[1:]:
        try:
            problems, counts = check(path, parser)
        except Exception as e:  # the reader refused the document
            problems, counts = [f"parse error: {e}"], {}
        if problems:
            failed = True
            for p in problems:
                print(f"{path}: {p}")
        else:
            print(
                f"{path}: read {counts['pous']} POU(s), {counts['steps']} steps, "
                f"{counts['transitions']} transitions"
            )
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
