fn main() {
    println!(
        "Bsdf {} Lobe {} SurfaceHit {} Hit {} LightSample {} Ray {} Sampler {}",
        std::mem::size_of::<prism::bsdf::Bsdf>(),
        std::mem::size_of::<prism::bsdf::Lobe>(),
        std::mem::size_of::<prism::primitives::SurfaceHit>(),
        std::mem::size_of::<prism::primitives::Hit>(),
        std::mem::size_of::<prism::lights::LightSample>(),
        std::mem::size_of::<prism::geometry::Ray>(),
        std::mem::size_of::<prism::sampling::Sampler>()
    );
}
