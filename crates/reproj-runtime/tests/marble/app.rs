//! The test app: the marble session's scene (built with reproj-replay's GPU-free modules: session
//! animation, the torus mesh, the shader's uniform reflection and packing, so that it draws the
//! scene `reproj render` draws), its own frame and depth targets, vertex stage and bind groups, and
//! the variant run through the runtime.

use std::fmt::Write as _;
use std::num::NonZeroU64;
use std::sync::{Arc, Mutex};

use bytemuck::{Pod, Zeroable};
use reproj_runtime::{
    FrameInputs, FrameTargets, Setup, SharedGroup, Variant, VariantResources, VertexStage,
};
use reproj_scene::reflect::{self, ResourceKind};
use reproj_scene::session::Cull;
use reproj_scene::{Session, mesh, uniforms};

use crate::common::workspace;

/// Frames per run: the cache is reused many times at Δn = 8 and the ping-pong wraps.
pub const FRAMES: u32 = 12;
pub const COLOR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// The app's per-object group (the shader's `scene` uniform is in group 0, the variant's own
/// group is 1).
pub const OBJECT_GROUP: u32 = 2;

const VERTEX_ATTRIBUTES: [wgpu::VertexAttribute; 4] =
    wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2, 3 => Float32x4];
/// The torus's vertices (`mesh::Vertex`: position, normal, uv, tangent).
const VERTEX_BUFFERS: [Option<wgpu::VertexBufferLayout<'static>>; 1] =
    [Some(wgpu::VertexBufferLayout {
        array_stride: size_of::<mesh::Vertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &VERTEX_ATTRIBUTES,
    })];

/// Per-object vertex-stage uniform: this frame's and the previous frame's matrices.
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
#[repr(C)]
struct ObjectUniform {
    view_proj: [[f32; 4]; 4],
    prev_view_proj: [[f32; 4]; 4],
    model: [[f32; 4]; 4],
    prev_model: [[f32; 4]; 4],
    normal_matrix: [[f32; 4]; 4],
}

struct Object {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    count: u32,
    uniform: wgpu::Buffer,
    group: wgpu::BindGroup,
    /// Index of its pipeline among the vertex stages (one per culling mode).
    stage: usize,
}

/// The app: device, the marble scene, its targets.
pub struct App {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub session: Session,
    pub size: [u32; 2],
    pub frame: wgpu::Texture,
    pub frame_view: wgpu::TextureView,
    depth: wgpu::Texture,
    pub depth_view: wgpu::TextureView,
    scene_size: u32,
    scene_fields: Vec<reflect::UniformField>,
    scene_buffer: wgpu::Buffer,
    /// The `scene` uniform's layout entry (group 0, binding 0).
    scene_entry: wgpu::BindGroupLayoutEntry,
    pub scene_layout: wgpu::BindGroupLayout,
    pub scene_group: wgpu::BindGroup,
    pub object_layout: wgpu::BindGroupLayout,
    objects: Vec<Object>,
    culls: Vec<Cull>,
    pub errors: Arc<Mutex<Vec<String>>>,
}

fn open_device(features: wgpu::Features) -> (wgpu::Device, wgpu::Queue) {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle().with_env();
    desc.backends = wgpu::Backends::VULKAN.with_env();
    let instance = wgpu::Instance::new(desc);
    let adapter = pollster::block_on(instance.request_adapter(&Default::default()))
        .expect("a Vulkan adapter (lavapipe: scripts/ensure-vulkan.sh)");
    pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("runtime test app"),
        required_features: features,
        required_limits: adapter.limits(),
        ..Default::default()
    }))
    .expect("opening the device")
}

impl App {
    pub fn new(features: wgpu::Features) -> App {
        let (device, queue) = open_device(features);
        let errors: Arc<Mutex<Vec<String>>> = Arc::default();
        let sink = errors.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            sink.lock().unwrap().push(e.to_string());
        }));
        let root = workspace();
        let session = Session::load(root.join("sessions/marble.json")).unwrap();
        let source = std::fs::read_to_string(root.join("shaders/marble.wgsl")).unwrap();
        let module = naga::front::wgsl::parse_str(&source).unwrap();
        let info = naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::all(),
        )
        .validate(&module)
        .unwrap();
        let entry = reflect::fragment_entry_index(&module, "fs_main").unwrap();
        let iface = reflect::reflect(&module, &info, entry).unwrap();
        let [scene_res] = iface.resources.as_slice() else {
            panic!("marble has one resource, its `scene` uniform");
        };
        assert_eq!((scene_res.group, scene_res.binding), (0, 0));
        let ResourceKind::Uniform { size, fields } = &scene_res.kind else {
            panic!("`scene` is a uniform");
        };
        let locations: Vec<u32> = iface.inputs.iter().map(|i| i.location).collect();
        assert_eq!(
            locations,
            [0, 1, 4],
            "the vertex stage below writes marble's inputs"
        );

        let uniform_entry = |binding, visibility, size: u64| wgpu::BindGroupLayoutEntry {
            binding,
            visibility,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: NonZeroU64::new(size),
            },
            count: None,
        };
        let scene_entry = uniform_entry(0, wgpu::ShaderStages::FRAGMENT, u64::from(*size));
        let scene_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("scene"),
            entries: &[scene_entry],
        });
        let scene_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("scene"),
            size: u64::from((*size).max(16)),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let scene_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("scene"),
            layout: &scene_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: scene_buffer.as_entire_binding(),
            }],
        });
        let object_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("object"),
            entries: &[uniform_entry(
                0,
                wgpu::ShaderStages::VERTEX,
                size_of::<ObjectUniform>() as u64,
            )],
        });

        let mut culls = Vec::new();
        let mut objects = Vec::new();
        for o in &session.geometry.objects {
            let data = mesh::build(&session, &o.mesh).unwrap();
            let init = |contents: &[u8], usage| {
                wgpu::util::DeviceExt::create_buffer_init(
                    &device,
                    &wgpu::util::BufferInitDescriptor {
                        label: None,
                        contents,
                        usage,
                    },
                )
            };
            let uniform = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("object"),
                size: size_of::<ObjectUniform>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("object"),
                layout: &object_layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: uniform.as_entire_binding(),
                }],
            });
            let stage = culls.iter().position(|c| *c == o.cull).unwrap_or_else(|| {
                culls.push(o.cull);
                culls.len() - 1
            });
            objects.push(Object {
                vertices: init(
                    bytemuck::cast_slice(&data.vertices),
                    wgpu::BufferUsages::VERTEX,
                ),
                indices: init(
                    bytemuck::cast_slice(&data.indices),
                    wgpu::BufferUsages::INDEX,
                ),
                count: data.indices.len() as u32,
                uniform,
                group,
                stage,
            });
        }
        let [w, h] = session.resolution;
        let target = |label, format, usage| {
            let t = device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width: w,
                    height: h,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT | usage,
                view_formats: &[],
            });
            let v = t.create_view(&Default::default());
            (t, v)
        };
        let (frame, frame_view) = target("frame", COLOR, wgpu::TextureUsages::COPY_SRC);
        let (depth, depth_view) = target("depth", DEPTH, wgpu::TextureUsages::COPY_SRC);
        App {
            device,
            queue,
            size: [w, h],
            frame,
            frame_view,
            depth,
            depth_view,
            scene_size: *size,
            scene_fields: fields.clone(),
            scene_buffer,
            scene_entry,
            scene_layout,
            scene_group,
            object_layout,
            objects,
            culls,
            session,
            errors,
        }
    }

    /// The app's vertex stage for a variant: world position, normal and object position at
    /// marble's locations 0, 1 and 4, the invariant clip position and the manifest's previous
    /// clip position (its `vertex.wgsl` helper called with `vertex.inputs`).
    fn vertex_wgsl(&self, variant: &Variant) -> String {
        let c = variant.vertex();
        let args: Vec<&str> = c
            .inputs
            .iter()
            .map(|i| match i.name.as_str() {
                "prev_view_proj" => "object.prev_view_proj",
                "prev_model" => "object.prev_model",
                "view_proj" => "object.view_proj",
                "model" => "object.model",
                "position" => "v.position",
                other => panic!("the vertex contract needs `{other}`"),
            })
            .collect();
        let helper = c.wgsl.split("fn ").nth(1).unwrap();
        let helper = &helper[..helper.find('(').unwrap()];
        let mut s = format!(
            "struct Object {{ view_proj: mat4x4<f32>, prev_view_proj: mat4x4<f32>, model: mat4x4<f32>, prev_model: mat4x4<f32>, normal_matrix: mat4x4<f32> }};\n\
             @group({OBJECT_GROUP}) @binding(0) var<uniform> object: Object;\n\
             struct In {{ @location(0) position: vec3<f32>, @location(1) normal: vec3<f32>, @location(2) uv: vec2<f32>, @location(3) tangent: vec4<f32> }};\n\
             struct Out {{ @builtin(position) @invariant clip: vec4<f32>, @location(0) world: vec3<f32>, @location(1) normal: vec3<f32>, @location(4) object_pos: vec3<f32>, @location({}) prev_clip: vec4<f32> }};\n",
            c.prev_clip_location
                .expect("the test's variants reproject with the vertex stage")
        );
        s.push_str(&c.wgsl);
        let _ = write!(
            s,
            "\n@vertex\nfn vs_main(v: In) -> Out {{\n\
             let world = object.model * vec4<f32>(v.position, 1.0);\n\
             var out: Out;\n\
             out.clip = object.view_proj * world;\n\
             out.world = world.xyz;\n\
             out.normal = normalize((object.normal_matrix * vec4<f32>(v.normal, 0.0)).xyz);\n\
             out.object_pos = v.position;\n\
             out.prev_clip = {helper}({});\n\
             return out;\n}}\n",
            args.join(", ")
        );
        s
    }

    /// Write frame `f`'s object transforms and `scene` uniform.
    pub fn write_frame(&self, f: u32) {
        let st = self.session.frame_state(f);
        let prev = self.session.frame_state(f.saturating_sub(1));
        for (i, o) in self.objects.iter().enumerate() {
            let model = st.models[i];
            let normal = glam::Mat4::from_mat3(glam::Mat3::from_mat4(model).inverse().transpose());
            let u = ObjectUniform {
                view_proj: st.camera.view_proj.to_cols_array_2d(),
                prev_view_proj: prev.camera.view_proj.to_cols_array_2d(),
                model: model.to_cols_array_2d(),
                prev_model: prev.models[i].to_cols_array_2d(),
                normal_matrix: normal.to_cols_array_2d(),
            };
            self.queue
                .write_buffer(&o.uniform, 0, bytemuck::bytes_of(&u));
        }
        let bytes =
            uniforms::uniform_bytes(&self.session, &st, self.scene_size, &self.scene_fields);
        self.queue.write_buffer(&self.scene_buffer, 0, &bytes);
    }

    pub fn clear_color(&self) -> wgpu::Color {
        let [r, g, b, a] = self.session.background.map(f64::from);
        wgpu::Color { r, g, b, a }
    }

    /// The texels of `tex` (`bytes` per texel), row-major, top row first, as f32s.
    pub fn read(&self, tex: &wgpu::Texture, bytes: u32) -> Vec<f32> {
        bytemuck::pod_collect_to_vec::<u8, f32>(&self.read_bytes(tex, bytes))
    }

    /// The texels of `tex` (`bytes` per texel), row-major, top row first.
    pub fn read_bytes(&self, tex: &wgpu::Texture, bytes: u32) -> Vec<u8> {
        let [w, h] = self.size;
        let tight = w * bytes;
        let row =
            tight.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let buf = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: u64::from(row * h),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut enc = self.device.create_command_encoder(&Default::default());
        enc.copy_texture_to_buffer(
            tex.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &buf,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(row),
                    rows_per_image: Some(h),
                },
            },
            tex.size(),
        );
        self.queue.submit([enc.finish()]);
        buf.slice(..).map_async(wgpu::MapMode::Read, |r| r.unwrap());
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .unwrap();
        let data = buf.get_mapped_range(..).unwrap().to_vec();
        (0..h as usize)
            .flat_map(|y| data[y * row as usize..y * row as usize + tight as usize].to_vec())
            .collect()
    }

    /// Draw the app's objects with `pipelines` (one per vertex stage, [`App::stages`]).
    pub fn draw(&self, pass: &mut wgpu::RenderPass<'_>, pipelines: &[wgpu::RenderPipeline]) {
        for o in &self.objects {
            pass.set_pipeline(&pipelines[o.stage]);
            pass.set_bind_group(OBJECT_GROUP, &o.group, &[]);
            pass.set_vertex_buffer(0, o.vertices.slice(..));
            pass.set_index_buffer(o.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..o.count, 0, 0..1);
        }
    }

    /// The app's vertex module for `variant` and its vertex buffer layout.
    pub fn vertex_module(&self, variant: &Variant) -> wgpu::ShaderModule {
        self.device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("app vertex stage"),
                source: wgpu::ShaderSource::Wgsl(self.vertex_wgsl(variant).into()),
            })
    }

    /// One vertex stage per culling mode of the scene's objects.
    pub fn stages<'a>(&self, vs: &'a wgpu::ShaderModule) -> Vec<VertexStage<'a>> {
        self.culls
            .iter()
            .map(|c| VertexStage {
                module: vs,
                entry_point: "vs_main",
                buffers: &VERTEX_BUFFERS,
                primitive: wgpu::PrimitiveState {
                    cull_mode: (*c == Cull::Back).then_some(wgpu::Face::Back),
                    ..Default::default()
                },
            })
            .collect()
    }

    /// Build `variant` for the app (its vertex stages from [`App::stages`]). Where the variant
    /// shares group 0 with marble's `scene` uniform (`reproj instance --group 0`), the app gives
    /// the uniform as the shared group's binding instead of a bind group of its own.
    pub fn create(&self, variant: &Variant, stages: &[VertexStage<'_>]) -> VariantResources {
        self.create_with(variant, stages, None)
    }

    /// [`App::create`], with the debug classification entry built into `classification`'s format.
    pub fn create_with(
        &self,
        variant: &Variant,
        stages: &[VertexStage<'_>],
        classification: Option<wgpu::TextureFormat>,
    ) -> VariantResources {
        assert!(
            !variant.reserved_groups().contains(&OBJECT_GROUP),
            "the app's object group is free"
        );
        let scene_entry = [self.scene_entry];
        let scene_resource = [wgpu::BindGroupEntry {
            binding: 0,
            resource: self.scene_buffer.as_entire_binding(),
        }];
        let shares = variant.shares_group();
        let own = [(0, &self.scene_layout), (OBJECT_GROUP, &self.object_layout)];
        variant
            .create(
                &self.device,
                &Setup {
                    size: self.size,
                    color_format: COLOR,
                    vertex: stages,
                    bind_group_layouts: if shares { &own[1..] } else { &own },
                    classification,
                    motion: None,
                    shared: shares.then_some(SharedGroup {
                        layout: &scene_entry,
                        resources: &scene_resource,
                    }),
                },
            )
            .unwrap()
    }

    /// Run [`FRAMES`] frames of `variant` through `gpu`, from the session's frame 0 (`restart`:
    /// asking the runtime to start over on it; else its clock must be at 0); the frames, and the
    /// last frame's depth target.
    pub fn run(
        &self,
        variant: &Variant,
        gpu: &mut VariantResources,
        restart: bool,
    ) -> (Vec<Vec<f32>>, Vec<f32>) {
        self.run_over(variant, gpu, restart, 1.0)
    }

    /// [`App::run`], the depth target cleared to `engine_depth` before each frame when the
    /// variant loads it (what the app's own opaque geometry would leave: 1.0 for none).
    pub fn run_over(
        &self,
        variant: &Variant,
        gpu: &mut VariantResources,
        restart: bool,
        engine_depth: f32,
    ) -> (Vec<Vec<f32>>, Vec<f32>) {
        let mut frames = Vec::new();
        for f in 0..FRAMES {
            if !(restart && f == 0) {
                assert_eq!(gpu.frame(), f);
            }
            self.write_frame(f);
            let mut enc = self.device.create_command_encoder(&Default::default());
            if variant.loads_frame_first() {
                // What lies behind the variant: here, the background.
                enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("background"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: &self.frame_view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(self.clear_color()),
                            store: wgpu::StoreOp::Store,
                        },
                    })],
                    ..Default::default()
                });
            }
            if variant.loads_depth_first() {
                // The engine's depth, as its opaque geometry would leave it.
                enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("engine depth"),
                    color_attachments: &[],
                    depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                        view: &self.depth_view,
                        depth_ops: Some(wgpu::Operations {
                            load: wgpu::LoadOp::Clear(engine_depth),
                            store: wgpu::StoreOp::Store,
                        }),
                        stencil_ops: None,
                    }),
                    ..Default::default()
                });
            }
            let targets = FrameTargets {
                color: &self.frame_view,
                depth: &self.depth_view,
                clear_color: self.clear_color(),
            };
            let scene = [(0, &self.scene_group)];
            let inputs = FrameInputs {
                bind_groups: if variant.shares_group() { &[] } else { &scene },
                restart: restart && f == 0,
                ..Default::default()
            };
            gpu.record(
                &self.queue,
                &mut enc,
                &targets,
                &inputs,
                |pass, pipelines| self.draw(pass, pipelines),
            )
            .unwrap();
            self.queue.submit([enc.finish()]);
            frames.push(self.read(&self.frame, 16));
            let errors = std::mem::take(&mut *self.errors.lock().unwrap());
            assert!(errors.is_empty(), "frame {f}: wgpu errors: {errors:#?}");
        }
        (frames, self.read(&self.depth, 4))
    }
}
