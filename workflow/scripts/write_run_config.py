"""Write the simulator's run config (YAML) for one run, from snakemake.params.run.

Used by the *_run_config rules of every paper (e.g. GRW05 Example 3 behind Table 1 and Fig. 1):
the simulator reads its config by path, so the workflow writes it from the Snakemake config;
the file stays next to the run's output as the record of what was run.
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import yaml  # noqa: E402

from granboltz.output.files import atomic_path  # noqa: E402

text = "# written by workflow/scripts/write_run_config.py from the Snakemake config\n"
text += yaml.safe_dump(dict(snakemake.params.run), sort_keys=False)
with atomic_path(snakemake.output.yaml) as tmp:
    with open(tmp, "w") as out:
        out.write(text)
print(text, file=sys.stderr)
