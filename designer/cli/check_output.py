"""``designer check-output OUT``: do a folder's images and ground truth still match its project?"""

from __future__ import annotations

import json
from pathlib import Path


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "check-output", help="check that a render folder's images and ground truth match "
                             "its project",
        description=(
            "Compare every image and the ground truth in an output folder of 'designer "
            "render' with what its project makes now (the manifest records, per image, "
            "the hashes of what it was rendered from). Lists images that are up to date, "
            "out of date (and what changed), missing, or not made by the project. Exit "
            "code 0 when everything matches, 1 when something does not."),
    )
    parser.add_argument("output", type=Path, help="output folder of 'designer render'")
    parser.add_argument("--project", type=Path, default=None,
                        help="project file (default: the one the manifest names)")
    parser.add_argument("--json", action="store_true", help="print the status as JSON")
    parser.set_defaults(func=run)


def run(args) -> int:
    from designer.render.check_output import check_output

    status = check_output(args.output, args.project)
    print(json.dumps(status.to_json(), indent=1) if args.json else status.summary())
    return 0 if status.ok else 1
