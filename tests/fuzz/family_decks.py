"""The decks of the fuzz families (families.py, system_families.py): a block of meshes/block.geo
held at its bottom under its own weight, with what each family needs of it."""

CHECKPOINT_STEPS = 20
FAIL_TIME = "{type: static, steps: 3, schedule: [0.5, 1.0, 1000], max_cutbacks: 0}"  # step 3 inverts

BLOCK = """mesh:
  file: {file}
{order}{parameters}materials:
  - {{group: body, model: neo_hookean, E: {E}, nu: 0.3, density: 1000}}
boundary:
  - {{group: bottom}}
loads:
  gravity: [0, 0, -9.81]
{pressure}time: {time}
solver: {{preset: mumps}}
{output}"""


def block_deck(geo, h=0.5, order=1, E="1.0e6", pressure="", time="{type: static, steps: 1}", output="", file=None):
    parameters = f"  parameters: {{h: {h}}}\n" if file is None else ""
    order = f"  order: {order}\n" if order else ""  # an .h5 mesh has the order it was meshed at
    return BLOCK.format(file=file or geo, order=order, parameters=parameters, E=E, pressure=pressure, time=time,
                        output=output)


def checkpoint_deck(geo):
    """A block that sags in 20 load steps, a checkpoint after each."""
    return block_deck(geo, h=0.2, E="2.0e5", time=f"{{type: static, steps: {CHECKPOINT_STEPS}}}",
                      output="output:\n  checkpoint: {every: 1}\n")


def h5_deck(mesh, order):
    """The .h5 cases' deck: a pressure on the top face, so that a face's orientation matters."""
    return block_deck(None, order=None, file=mesh, pressure="  pressure:\n    - {group: top, value: 2.0e4}\n")
