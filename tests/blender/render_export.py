"""Render a ``blender/`` export with bpy (Cycles, CPU): run by the Python that has ``bpy``.

    python render_export.py EXPORT_DIR X Y Z YAW PITCH FOV HEIGHT WIDTH SAMPLES OUT.png

Runs the export's script as Blender would (its ``build_material(unlit=True)``), puts the material
on a large plane at Z = 0 under spectex's camera (x east = X, y north = Y, z up = Z; yaw 0 looks
along +Y, pitch down negative, fov vertical), black world, View Transform Standard, and writes a
16-bit PNG. Prints the lines the export's script printed.
"""

import math
import runpy
import sys

import bpy


def main(argv):
    folder, x, y, z, yaw, pitch, fov, height, width, samples, out = argv
    x, y, z, yaw, pitch, fov = map(float, (x, y, z, yaw, pitch, fov))
    bpy.ops.wm.read_factory_settings(use_empty=True)
    script = runpy.run_path(f"{folder}/blender/spectex_ground.py", run_name="spectex_ground")
    material = script["build_material"](unlit=True)
    bpy.ops.mesh.primitive_plane_add(size=8000.0, location=(x, y, 0.0))
    plane = bpy.context.active_object
    plane.data.materials.append(material)
    cam_data = bpy.data.cameras.new("camera")
    cam_data.sensor_fit = "VERTICAL"
    cam_data.angle_y = math.radians(fov)
    cam_data.clip_end = 1e5
    cam = bpy.data.objects.new("camera", cam_data)
    bpy.context.scene.collection.objects.link(cam)
    cam.location = (x, y, z)
    # Blender's camera looks along -Z; X by 90 + pitch degrees tips it to +Y and down, Z by -yaw turns it east
    cam.rotation_euler = (math.radians(90.0 + pitch), 0.0, math.radians(-yaw))
    scene = bpy.context.scene
    scene.camera = cam
    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0, 0, 0, 1)
    scene.world = world
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = int(samples)
    scene.cycles.use_denoising = False
    scene.cycles.use_adaptive_sampling = False
    # a box of 1 px: each pixel the mean of the linear light over its square (the test's reference is that)
    scene.cycles.pixel_filter_type = "BOX"
    scene.cycles.filter_width = 1.0
    scene.render.threads_mode = "FIXED"
    scene.render.threads = 2
    scene.render.resolution_x, scene.render.resolution_y = int(width), int(height)
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_depth = "16"
    scene.render.image_settings.color_mode = "RGB"
    scene.render.filepath = out
    bpy.ops.render.render(write_still=True)


if __name__ == "__main__":
    main(sys.argv[1:])
