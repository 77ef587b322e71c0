"""The water material preset: clear, refracting water (index of refraction
1.333) for Cycles and Eevee; one material shared by every imported run."""

import bpy

NAME = "pbf Water"


def _set_input(node, names, value):
    """Principled BSDF inputs were renamed in Blender 4 ('Transmission' ->
    'Transmission Weight'): set the first name this version has."""
    for name in names:
        if name in node.inputs:
            node.inputs[name].default_value = value
            return


def water_material():
    material = bpy.data.materials.get(NAME)
    if material is not None:
        return material
    material = bpy.data.materials.new(NAME)
    material.use_nodes = True
    bsdf = next(n for n in material.node_tree.nodes if n.type == "BSDF_PRINCIPLED")
    _set_input(bsdf, ["Base Color"], (0.80, 0.92, 1.0, 1.0))
    _set_input(bsdf, ["Roughness"], 0.02)
    _set_input(bsdf, ["IOR"], 1.333)
    _set_input(bsdf, ["Transmission Weight", "Transmission"], 1.0)
    material.diffuse_color = (0.55, 0.75, 0.95, 0.6)  # solid viewport
    # Eevee: refraction through the surface instead of an opaque look.
    if hasattr(material, "use_screen_refraction"):
        material.use_screen_refraction = True
    if hasattr(material, "blend_method"):
        material.blend_method = "BLEND"
    return material
