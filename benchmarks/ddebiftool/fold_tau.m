function fold_tau(tau,kstart,degree,intervals)
%% fold of cycles on the branch from the Hopf point at delay tau
setup_path();
t0=tic;
[hopf,~,funcs,ip,hbr]=hopf_point(tau,kstart);
[pbr,suc]=SetupPsol(funcs,hbr,1,'contpar',[ip.k,ip.c],'degree',degree,...
    'intervals',intervals,'radius',1e-3,'max_bound',[ip.k,30],'min_bound',[ip.k,0.02]);
if ~suc, error('psol init failed'); end
pbr.method.continuation.plot=0;
pbr.method.point.extra_condition=1;   % activate the pinning z(0)=0 (sys_cond)
pbr.method.continuation.steplength_growth_factor=1.2;
pbr.method.point.adapt_mesh_after_correct=1;
pbr.method.point.adapt_mesh_before_correct=1;
pbr.parameter.max_step=[ip.k,0.3;0,0.6];
% continue in chunks until k has turned (3 points past the minimum)
for it=1:30
    pbr=br_contn(funcs,pbr,10);
    k=orbit_measures(pbr.point,ip); [~,i]=min(k);
    if i<numel(k)-2 && k(end)>k(i)*1.05, break; end
end
[kf,Tf,fine]=fold_refine(funcs,pbr,ip);
fprintf('FOLDFIT tau=%g k_fold=%.6f T_fold=%.6f (vertex of quadratic fit)\n',tau,kf,Tf);
[kp,Tp,~,~,sp]=pofold_point(funcs,fine,ip);
fprintf('POFOLD tau=%g success=%d k_fold=%.8f T_fold=%.8f\n',tau,sp,kp,Tp);
% Floquet multipliers at the fine point nearest the fold
[kk]=orbit_measures(fine.point,ip); [~,j]=min(kk);
[~,~,~,pt]=GetStability(fine,'funcs',funcs,'points',j,'exclude_trivial',true,'locate_trivial',@(p)[1;1]);
mu=pt.stability.mu; [~,o]=sort(abs(mu),'descend');
fprintf('FOLDSUMMARY tau=%g k_fold(fit)=%.6f T_fold(fit)=%.6f (k_H=%.6f) mult. nearest fold: %s  runtime=%.0fs\n',...
    tau,kf,Tf,hopf.parameter(ip.k),mat2str(abs(mu(o(1:4)))',5),toc(t0));
end
