"""``vslsp pddl check DOMAIN [PROBLEM]``: read PDDL 3.0 files and report what is in them or wrong."""

from __future__ import annotations

import json

import click


@click.group()
def pddl() -> None:
    """Work with PDDL 3.0 domain and problem files."""


@pddl.command()
@click.argument("domain", type=click.Path(dir_okay=False))
@click.argument("problem", type=click.Path(dir_okay=False), required=False)
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object on stdout.")
def check(domain: str, problem: str | None, as_json: bool) -> None:
    """Parse DOMAIN (and PROBLEM); malformed input is reported as FILE:LINE:COL (exit 2)."""
    from vslsp.symbolic import read_pddl

    parsed_domain, parsed_problem = read_pddl(domain, problem)
    summary = {"domain": {
        "name": parsed_domain.name,
        "types": [name for name, _ in parsed_domain.types],
        "predicates": [p.name for p in parsed_domain.predicates],
        "actions": [a.name for a in parsed_domain.actions],
    }}
    if parsed_problem is not None:
        summary["problem"] = {
            "name": parsed_problem.name,
            "objects": [name for name, _ in parsed_problem.objects],
            "init": sorted(atom.to_pddl() for atom in parsed_problem.init),
            "goal": parsed_problem.goal.to_pddl(),
            "constraints": [c.to_pddl() for c in parsed_problem.constraints],
        }
    if as_json:
        click.echo(json.dumps(summary))
        return
    d = summary["domain"]
    click.echo(f"{domain}: domain {d['name']}: {len(d['types'])} type(s), predicates {', '.join(d['predicates'])}; "
               f"actions {', '.join(d['actions'])}")
    if parsed_problem is not None:
        p = summary["problem"]
        click.echo(f"{problem}: problem {p['name']}: {len(p['objects'])} object(s), {len(p['init'])} true atom(s) "
                   f"initially, goal {p['goal']}, {len(p['constraints'])} constraint(s)")
        for constraint in p["constraints"]:
            click.echo(f"  {constraint}")
    click.echo("ok")


@pddl.command()
@click.argument("domain", type=click.Path(dir_okay=False), required=False)
@click.argument("problem", type=click.Path(dir_okay=False), required=False)
def shell(domain: str | None, problem: str | None) -> None:
    """Author a domain and a problem interactively (tab completion, history); plan and validate."""
    from vslsp.symbolic import read_pddl
    from vslsp.symbolic.shell import Shell

    parsed_domain, parsed_problem = read_pddl(domain, problem) if domain else (None, None)
    Shell(parsed_domain, parsed_problem).cmdloop()
