@tool
extends MeshInstance3D
## spectex ground: keeps the layer anchors of spectex_ground.gdshader next to the camera,
## computed in float64 (GDScript floats), so the texture stays precise far from the origin.
## Attach to the MeshInstance3D that carries the spectex ground material (material_override
## or surface 0). With follow_camera, the mesh also moves with the camera in x and z (an
## endless ground plane; the texture stays fixed to the world).

## Per layer: m00, m01, m10, m11 (world metres -> tile coordinates), offset x, offset y (metres);
## for a stochastic layer also g00, g01, g10, g11 (tile coordinates -> triangle-grid coordinates).
const LAYERS = [
{{#each layers}}
	[{{row}}],
{{/each}}
]
{{#if stochastic}}
## The stochastic layers' tables: raw little-endian half floats beside this script.
const GAUSS_FILES = [{{gauss_files}}]
const GAUSS_SIZE = Vector2i({{gauss_width}}, {{gauss_height}})
const LUT_FILE = "{{lut_file}}"
const LUT_SIZE = Vector2i({{lut_width}}, {{lut_height}})
{{/if}}

@export var follow_camera := true
## The anchor point moves in steps of this many metres (it only needs to stay near the camera).
@export var anchor_step := 256.0

{{#if stochastic}}
var _tables_for: ShaderMaterial = null


## Give the material the stochastic tables, every mip level as spectex made it (no import).
func _load_tables(material: ShaderMaterial) -> void:
	var folder: String = get_script().resource_path.get_base_dir()
	for i in GAUSS_FILES.size():
		var data := FileAccess.get_file_as_bytes(folder.path_join(GAUSS_FILES[i]))
		var image := Image.create_from_data(GAUSS_SIZE.x, GAUSS_SIZE.y, true, Image.FORMAT_RGBAH, data)
		material.set_shader_parameter("spectex_gauss%d" % i, ImageTexture.create_from_image(image))
	var lut := FileAccess.get_file_as_bytes(folder.path_join(LUT_FILE))
	var lut_image := Image.create_from_data(LUT_SIZE.x, LUT_SIZE.y, false, Image.FORMAT_RH, lut)
	material.set_shader_parameter("spectex_lut_texture", ImageTexture.create_from_image(lut_image))
	_tables_for = material

{{/if}}

func _process(_delta: float) -> void:
	var camera := get_viewport().get_camera_3d()
	if camera == null:
		return
	var material := material_override as ShaderMaterial
	if material == null:
		material = get_active_material(0) as ShaderMaterial
	if material == null:
		return
{{#if stochastic}}
	if material != _tables_for:
		_load_tables(material)
{{/if}}
	var eye := camera.global_position
	if follow_camera:
		global_position = Vector3(eye.x, global_position.y, eye.z)
	var scale = material.get_shader_parameter("spectex_metres_per_unit")
	if scale == null or scale <= 0.0:
		scale = 1.0
	# spectex ground coordinates: x = world X, y = -world Z (metres)
	var ax := snappedf(eye.x * scale, anchor_step)
	var ay := snappedf(-eye.z * scale, anchor_step)
	var anchors := PackedVector2Array()
	var ganchors := PackedVector2Array()
	var gbase := PackedInt32Array()
	for layer in LAYERS:
		var dx: float = ax - layer[4]
		var dy: float = ay - layer[5]
		var s: float = layer[0] * dx + layer[1] * dy
		var t: float = layer[2] * dx + layer[3] * dy
		anchors.append(Vector2(fposmod(s, {{anchor_period}}), fposmod(t, {{anchor_period}})))
		if layer.size() > 6:
			# the grid position of the unreduced (s, t): its fraction, and its vertex mod 2^32
			var kx: float = layer[6] * s + layer[7] * t
			var ky: float = layer[8] * s + layer[9] * t
			ganchors.append(Vector2(kx - floorf(kx), ky - floorf(ky)))
			gbase.append(_uint_bits(int(floorf(kx))))
			gbase.append(_uint_bits(int(floorf(ky))))
		else:
			ganchors.append(Vector2.ZERO)
			gbase.append(0)
			gbase.append(0)
	material.set_shader_parameter("spectex_anchored", true)
	material.set_shader_parameter("spectex_anchor_point", Vector2(ax, ay))
	material.set_shader_parameter("spectex_anchor", anchors)
{{#if stochastic}}
	material.set_shader_parameter("spectex_ganchor", ganchors)
	material.set_shader_parameter("spectex_gbase", gbase)
{{/if}}


## v mod 2^32 as the int32 with the same bits (the shader reads them as a uint).
func _uint_bits(v: int) -> int:
	var u := posmod(v, 4294967296)
	return u - 4294967296 if u >= 2147483648 else u
