#!/usr/bin/env python3
"""A GLB written by csgkit imports into Blender with its materials and colours.

Two cubes are written as 3MF files with a base material each ("stone", red; "glass", blue),
csgkit unites them into a GLB (`csgkit union a.3mf b.3mf -o out.glb`), and Blender's glTF
importer (bpy, Blender as a Python module) loads it; the script prints the objects, the
materials with their base colours and the triangle count, and checks that both materials
arrive with their colours. With a FILE argument it imports that GLB instead and only prints.

bpy needs its own Python (3.11 for bpy 4.x and 5.0):
    python3.11 -m venv /work/venv-blender && /work/venv-blender/bin/pip install bpy
    cargo build --release -p csgkit-cli
    /work/venv-blender/bin/python scripts/blender_gltf_check.py --csgkit target/release/csgkit [FILE.glb]
Exits 1 if a check fails.
"""

import argparse
import pathlib
import subprocess
import sys
import tempfile
import zipfile

import bpy

REPO = pathlib.Path(__file__).resolve().parent.parent
CORE = "http://schemas.microsoft.com/3dmanufacturing/core/2015/02"

# The 12 outward triangles of the cube over corners (x, y, z) indexed x + 2y + 4z.
CUBE_TRIANGLES = [
    (0, 2, 1), (1, 2, 3), (4, 5, 6), (5, 7, 6), (0, 1, 4), (1, 5, 4),
    (2, 6, 3), (3, 6, 7), (0, 4, 2), (2, 4, 6), (1, 3, 5), (3, 7, 5),
]


def cube_3mf(path, low, high, material, color):
    """A 3MF of the cube [low, high]^3, every triangle of `material` with display `color`."""
    corners = [(x, y, z) for z in (low, high) for y in (low, high) for x in (low, high)]
    vertices = "".join(f'<vertex x="{x}" y="{y}" z="{z}"/>' for x, y, z in corners)
    triangles = "".join(
        f'<triangle v1="{a}" v2="{b}" v3="{c}" pid="1" p1="0"/>' for a, b, c in CUBE_TRIANGLES
    )
    model = (
        f'<?xml version="1.0" encoding="UTF-8"?><model unit="millimeter" xmlns="{CORE}">'
        f'<resources><basematerials id="1"><base name="{material}" displaycolor="{color}"/>'
        f'</basematerials><object id="2" type="model"><mesh><vertices>{vertices}</vertices>'
        f"<triangles>{triangles}</triangles></mesh></object></resources>"
        f'<build><item objectid="2"/></build></model>'
    )
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as archive:
        archive.writestr("3D/3dmodel.model", model)


def base_color(material):
    """The Base Color of the material's Principled BSDF, as RGBA floats."""
    if material.node_tree is not None:
        for node in material.node_tree.nodes:
            if node.type == "BSDF_PRINCIPLED":
                return tuple(round(c, 4) for c in node.inputs["Base Color"].default_value)
    return tuple(round(c, 4) for c in material.diffuse_color)


def import_glb(path):
    """Imports `path` into an empty scene; returns the mesh objects, materials and triangles."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=str(path))
    objects = [o for o in bpy.context.scene.objects if o.type == "MESH"]
    materials = {}
    triangles = 0
    for obj in objects:
        mesh = obj.data
        mesh.calc_loop_triangles()
        triangles += len(mesh.loop_triangles)
        for slot in obj.material_slots:
            if slot.material is not None:
                materials[slot.material.name] = base_color(slot.material)
    return objects, materials, triangles


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--csgkit", default=str(REPO / "target" / "release" / "csgkit"))
    parser.add_argument("file", nargs="?", help="a GLB to import instead of the generated one")
    args = parser.parse_args()
    print(f"Blender {bpy.app.version_string}")
    with tempfile.TemporaryDirectory() as tmp:
        folder = pathlib.Path(tmp)
        if args.file:
            glb = pathlib.Path(args.file)
        else:
            cube_3mf(folder / "a.3mf", 0, 2, "stone", "#FF0000FF")
            cube_3mf(folder / "b.3mf", 1, 3, "glass", "#0000FFFF")
            glb = folder / "union.glb"
            subprocess.run(
                [args.csgkit, "union", folder / "a.3mf", folder / "b.3mf", "-o", glb], check=True
            )
        objects, materials, triangles = import_glb(glb)
        print(f"{glb.name}: {len(objects)} mesh object(s), {triangles} triangles, "
              f"{len(materials)} material(s)")
        for name, color in sorted(materials.items()):
            print(f"  material {name!r}: base colour {color}")
        if args.file:
            return 0
        expected = {"stone": (1.0, 0.0, 0.0, 1.0), "glass": (0.0, 0.0, 1.0, 1.0)}
        ok = len(objects) == 1 and materials == expected
        print("materials and colours arrived" if ok else f"FAILED: expected {expected}")
        return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
