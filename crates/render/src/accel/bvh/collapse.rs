//! Collapsing the binary tree into N-wide nodes for traversal (as Embree's
//! BVH4 and BVH8, Wald et al. 2014).

use super::build::BuildNode;
use crate::accel::node::Node;

/// Collapses the binary tree into N-wide nodes: each node takes its
/// children's children, opening the largest interior child first, until
/// it has N. Node 0 is the root.
pub(super) fn collapse<const N: usize>(
    root: &BuildNode,
    leaves: &mut Vec<(u32, u32)>,
) -> Vec<Node<N>> {
    let mut nodes = vec![Node::EMPTY];
    let top: Vec<&BuildNode> = match root {
        // A lone leaf still needs a node above it.
        BuildNode::Leaf { .. } => vec![root],
        BuildNode::Interior { children, .. } => vec![&children[0], &children[1]],
    };
    fill(0, top, &mut nodes, leaves);
    nodes
}

fn fill<const N: usize>(
    at: usize,
    mut kids: Vec<&BuildNode>,
    nodes: &mut Vec<Node<N>>,
    leaves: &mut Vec<(u32, u32)>,
) {
    while kids.len() < N {
        let widest = kids
            .iter()
            .enumerate()
            .filter(|(_, k)| matches!(k, BuildNode::Interior { .. }))
            .max_by(|a, b| a.1.bounds().area().total_cmp(&b.1.bounds().area()))
            .map(|(i, _)| i);
        let Some(i) = widest else { break };
        let BuildNode::Interior { children, .. } = kids.swap_remove(i) else {
            unreachable!("filtered to interior nodes")
        };
        kids.push(&children[0]);
        kids.push(&children[1]);
    }
    for (c, kid) in kids.into_iter().enumerate() {
        let b = kid.bounds();
        let corners = [b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z];
        for (k, v) in corners.into_iter().enumerate() {
            nodes[at].bounds[k][c] = v;
        }
        match kid {
            BuildNode::Leaf { start, count, .. } => {
                nodes[at].child[c] = leaves.len() as u32;
                nodes[at].count[c] = (*count).clamp(1, u16::MAX as usize) as u16;
                leaves.push((*start as u32, *count as u32));
            }
            BuildNode::Interior { children, .. } => {
                let index = nodes.len();
                nodes.push(Node::EMPTY);
                nodes[at].child[c] = index as u32;
                fill(index, vec![&children[0], &children[1]], nodes, leaves);
            }
        }
    }
}
